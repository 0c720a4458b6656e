// The plain values the drive exchanges with its object dictionary each cycle
// (CiA 402-2 §8-§14). DriveInputs holds what the drive reads (RxPDO objects
// and parameters written by SDO), DriveOutputs what it writes (TxPDO
// objects). Types and units as the profile defines them: positions in
// position units, velocities in velocity units (position units per second),
// accelerations in position units/s², torques in per mille of rated torque.
// ds402::DriveBinding copies these from/to the coe::ObjectStore.
#pragma once

#include <cstddef>
#include <cstdint>

#include "common/cache_line.hpp"

namespace ecat::ds402 {

// DriveInputs' members are ordered by use, not by index: what a cycle reads whatever
// the mode comes first, so that those values sit in the fewest cache lines
// beside DriveOutputs (slave::DriveApplication keeps both together; issue
// 30 item 1: at 1000 drives each line a cycle touches is a cache miss).
// Build one as `DriveInputs in{}` and set members by name.
struct DriveInputs {
  // Read every cycle, packed without gaps (DriveOutputs and these fill
  // three cache lines).
  std::uint16_t controlword = 0;          // 6040h
  std::int8_t modes_of_operation = 0;     // 6060h
  // Not an object: set by the synchronisation layer when the cyclic
  // set-points stopped arriving in time (SM2/Sync0 watchdog, 1C32h errors).
  bool sync_lost = false;
  std::int32_t target_position = 0;       // 607Ah
  std::int32_t target_velocity = 0;       // 60FFh
  std::int32_t position_offset = 0;       // 60B0h
  std::int32_t velocity_offset = 0;       // 60B1h
  std::int16_t target_torque = 0;         // 6071h
  std::int16_t torque_offset = 0;         // 60B2h

  std::uint32_t max_profile_velocity = 0xFFFFFFFF;  // 607Fh
  std::uint32_t max_motor_speed = 0;                // 6080h, rpm (0: the plant's maximum)
  std::int32_t software_limit_min = 0;  // 607Dh:01 (min >= max: no limits)
  std::int32_t software_limit_max = 0;  // 607Dh:02
  std::uint16_t max_torque = 3000;               // 6072h, per mille
  std::uint16_t positive_torque_limit = 3000;    // 60E0h
  std::uint16_t negative_torque_limit = 3000;    // 60E1h
  std::uint16_t touch_probe_function = 0;        // 60B8h

  std::uint32_t following_error_window = 0xFFFFFFFF;  // 6065h (all ones: off)
  std::uint32_t position_window = 100;                // 6067h
  std::uint16_t following_error_timeout = 0;          // 6066h, ms
  std::uint16_t position_window_time = 0;             // 6068h, ms

  std::int16_t quick_stop_option = 2;         // 605Ah
  std::int16_t shutdown_option = 0;           // 605Bh
  std::int16_t disable_operation_option = 1;  // 605Ch
  std::int16_t halt_option = 1;               // 605Dh
  std::int16_t fault_reaction_option = 2;     // 605Eh
  // Interpolation data configuration 60C4h (ds402/ip_buffer.hpp): what a
  // cycle reads of it.
  std::uint16_t ip_buffer_position = 0;      // 60C4h:04

  // Factor group (CiA 402-2 §6.3). 0 in a feed/encoder field means "one
  // position unit per encoder increment".
  std::uint32_t encoder_increments = 0;  // 608Fh:01
  std::uint32_t motor_revolutions = 1;   // 608Fh:02
  std::uint32_t gear_motor_revolutions = 1;  // 6091h:01
  std::uint32_t gear_shaft_revolutions = 1;  // 6091h:02
  std::uint32_t feed = 0;                    // 6092h:01
  std::uint32_t feed_shaft_revolutions = 1;  // 6092h:02
  // The vl scaling (velocity mode vl below), read with the factor group.
  std::int32_t vl_dimension_numerator = 1;         // 604Ch:01
  std::int32_t vl_dimension_denominator = 1;       // 604Ch:02
  std::int16_t vl_setpoint_numerator = 1;          // 604Bh:01
  std::int16_t vl_setpoint_denominator = 1;        // 604Bh:02

  std::uint8_t ip_buffer_access = 0;         // 60C4h:06 (0 clear/disabled, 1 enabled)
  // Not an object: 60C1h:01 was written since the last cycle (by SDO, or by
  // the RxPDO that maps it), so ip_position is a new record for the buffer.
  bool ip_record_new = false;

  // Read in their modes, or when they change.
  std::uint32_t profile_velocity = 100000;          // 6081h
  std::uint32_t profile_acceleration = 1000000;     // 6083h
  std::uint32_t profile_deceleration = 1000000;     // 6084h
  std::uint32_t quick_stop_deceleration = 4000000;  // 6085h
  std::uint32_t torque_slope = 10000;               // 6087h, per mille per second

  std::int8_t homing_method = 0;                // 6098h
  std::uint32_t homing_speed_switch = 50000;    // 6099h:01
  std::uint32_t homing_speed_zero = 10000;      // 6099h:02
  std::uint32_t homing_acceleration = 1000000;  // 609Ah
  std::int32_t home_offset = 0;                 // 607Ch
  // Current threshold of the current-threshold homing methods, mA (Welcon
  // 2402h, bound where the personality names it: DriveConfig).
  std::uint32_t homing_current_threshold = 100;

  std::uint16_t velocity_window = 100;                // 606Dh
  std::uint16_t velocity_window_time = 0;             // 606Eh, ms
  std::uint16_t velocity_threshold = 100;             // 606Fh
  std::uint16_t velocity_threshold_time = 0;          // 6070h, ms

  // Interpolated position mode (CiA 402-2 §13): linear interpolation only.
  std::int32_t ip_position = 0;        // 60C1h:01 interpolation data record, position
  std::uint8_t ip_period_value = 0;    // 60C2h:01 (0: one drive cycle)
  std::int8_t ip_period_index = -3;    // 60C2h:02, period = value · 10^index s
  std::uint32_t ip_buffer_actual_size = 16;  // 60C4h:02
  std::uint8_t ip_buffer_organisation = 0;   // 60C4h:03 (0 FIFO, 1 ring)

  // Velocity mode vl (CiA 402-2 vl objects; ds402/velocity_mode.hpp). Velocities
  // in vl units (rpm scaled by 604Ch), times in s (6048h-604Ah:02) or ms.
  std::int16_t vl_target_velocity = 0;             // 6042h
  std::uint32_t vl_min_amount = 0;                 // 6046h:01
  std::uint32_t vl_max_amount = 0xFFFFFFFF;        // 6046h:02
  std::uint32_t vl_acceleration_delta_speed = 0;   // 6048h:01
  std::uint16_t vl_acceleration_delta_time = 1;    // 6048h:02, s
  std::uint32_t vl_deceleration_delta_speed = 0;   // 6049h:01
  std::uint16_t vl_deceleration_delta_time = 1;    // 6049h:02, s
  std::uint32_t vl_quick_stop_delta_speed = 0;     // 604Ah:01
  std::uint16_t vl_quick_stop_delta_time = 1;      // 604Ah:02, s
  std::uint32_t vl_velocity_reference = 0;         // 604Eh
  std::uint32_t vl_ramp_function_time = 0;         // 604Fh, ms
  std::uint32_t vl_slow_down_time = 0;             // 6050h, ms
  std::uint32_t vl_quick_stop_time = 0;            // 6051h, ms
};

struct DriveOutputs {
  // Written every cycle; ordered to leave no gaps (see DriveInputs).
  std::uint16_t statusword = 0;             // 6041h
  std::int8_t modes_of_operation_display = 0;  // 6061h
  std::uint8_t error_register = 0;          // 1001h
  std::int32_t position_demand = 0;         // 6062h
  std::int32_t position_actual_internal = 0;  // 6063h, increments
  std::int32_t position_actual = 0;         // 6064h
  std::int32_t velocity_demand = 0;         // 606Bh
  std::int32_t velocity_actual = 0;         // 606Ch
  std::int32_t following_error = 0;         // 60F4h
  std::int32_t position_demand_internal = 0;  // 60FCh, increments
  std::int16_t torque_demand = 0;           // 6074h
  std::int16_t torque_actual = 0;           // 6077h
  std::uint16_t error_code = 0;             // 603Fh
  std::uint16_t touch_probe_status = 0;     // 60B9h
  std::int32_t touch_probe_1_positive = 0;  // 60BAh
  std::int32_t touch_probe_1_negative = 0;  // 60BBh
  std::int32_t touch_probe_2_positive = 0;  // 60BCh
  std::int32_t touch_probe_2_negative = 0;  // 60BDh
  std::uint32_t digital_inputs = 0;         // 60FDh
  std::uint32_t supported_drive_modes = 0;  // 6502h
  std::uint16_t ip_buffer_position = 0;     // 60C4h:04 (ring buffer: the next write position)
  std::int16_t vl_velocity_demand = 0;      // 6043h, vl units
  std::int16_t vl_velocity_actual = 0;      // 6044h, vl units
};

// The outputs and what a cycle reads of the inputs fill three cache lines
// when the two follow each other from a line's start (DriveApplication).
static_assert(sizeof(DriveOutputs) + offsetof(DriveInputs, ip_record_new) + sizeof(bool) <= 3 * kCacheLineBytes);

}  // namespace ecat::ds402
