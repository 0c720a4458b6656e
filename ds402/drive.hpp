// A simulated CiA 402 servo drive: the PDS state machine, the modes of
// operation, homing, touch probe, monitoring and a motor/load plant, stepped
// once per cycle with the plain object values (ds402/objects.hpp). It owns
// no object dictionary and never allocates after construction; time advances
// only by the cycle length passed to step().
#pragma once

#include <cstdint>
#include <optional>

#include "common/cache_line.hpp"
#include "common/clock.hpp"
#include "ds402/axis.hpp"
#include "ds402/drive_config.hpp"
#include "ds402/drive_overrides.hpp"
#include "ds402/faults.hpp"
#include "ds402/homing.hpp"
#include "ds402/ip_buffer.hpp"
#include "ds402/modes.hpp"
#include "ds402/objects.hpp"
#include "ds402/plant.hpp"
#include "ds402/profile.hpp"
#include "ds402/profile_position.hpp"
#include "ds402/state_machine.hpp"
#include "ds402/touch_probe.hpp"
#include "ds402/units.hpp"
#include "ds402/velocity_mode.hpp"

namespace ecat::ds402 {

// Aligned to a cache line: its cycle state is laid out by line (the members
// below), the same lines in every drive (issue 30 item 1).
class alignas(kCacheLineBytes) Drive {
 public:
  Drive(DriveConfig config, const PlantParameters& plant);

  // One drive cycle of length `cycle`: reads `in`, advances the simulation,
  // fills `out`.
  void step(const DriveInputs& in, DriveOutputs& out, Nanoseconds cycle) noexcept;

  PdsState state() const noexcept { return sm_.state(); }
  int last_transition() const noexcept { return sm_.last_transition(); }
  OperationMode mode() const noexcept { return mode_; }
  HomingStatus homing_status() const noexcept { return homing_.status(); }
  bool fault_latched(FaultKind k) const noexcept { return (latched_ >> static_cast<unsigned>(k)) & 1u; }
  const DriveConfig& config() const noexcept { return config_; }
  const Plant& plant() const noexcept { return plant_; }
  const Axis& axis() const noexcept { return axis_; }
  EmcyQueue& emergencies() noexcept { return emcy_; }
  const IpBuffer& ip_buffer() const noexcept { return ip_buffer_; }

  // Simulation hooks (tests, demos): a load torque against the motor.
  void set_external_torque(double nm) noexcept { plant_.set_external_torque(nm); }
  // Raises a fault as if the monitoring had found it.
  void raise_fault(FaultKind k) noexcept;
  // A fault from outside the drive's own monitoring (slave::FaultCatalogue:
  // over-current, over-voltage, encoder, ...) with the code 603Fh and the
  // emergency carry. While it is set the fault is present: it latches in the
  // next step (Fault, one EMCY) and a fault reset does not clear it (the
  // drive stays in Fault, 603Fh keeps the code); nullopt removes the cause,
  // so the next fault reset works.
  void set_external_fault(std::optional<FaultCode> fault) noexcept { external_ = fault; }
  bool external_fault_latched() const noexcept { return (latched_ & kExternalFaultBit) != 0; }
  // Terminals and brake forced from outside (ds402/drive_overrides.hpp),
  // from the next step on; a default DriveOverrides removes them.
  void set_overrides(const DriveOverrides& o) noexcept;
  const DriveOverrides& overrides() const noexcept { return overrides_; }

  // Logical position minus physical position (increments), set by homing.
  double home_shift() const noexcept { return home_shift_; }
  // Demand values of the last cycle in physical increments, increments/s and N·m.
  double position_demand() const noexcept { return demand_.position; }
  double velocity_demand() const noexcept { return demand_.velocity; }
  double torque_demand() const noexcept { return plant_.torque_command(); }

 private:
  struct Timer {  // time a condition has held, in seconds
    double held = 0;
    bool update(bool condition, double dt, double limit_s) noexcept {
      held = condition ? held + dt : 0;
      return condition && held >= limit_s;
    }
  };

  void select_mode(const DriveInputs& in) noexcept;
  void enter_mode() noexcept;
  void run_mode(const DriveInputs& in, double dt) noexcept;
  void run_interpolated(const DriveInputs& in, double dt) noexcept;
  void run_stop(StopKind stop, const DriveInputs& in, double dt) noexcept;
  void hold() noexcept;
  void monitor(const DriveInputs& in, double dt) noexcept;
  void clear_faults() noexcept;
  void raise_external_fault(const FaultCode& code) noexcept;
  // What the overrides change in the state machine's inputs (drive_overrides.cpp).
  void apply_overrides(StateMachine::Inputs& si) noexcept;
  std::uint32_t forced_digital_inputs() const noexcept;
  // 603Fh, 1001h and the EMCY of a fault just latched.
  void latch(const FaultCode& code) noexcept;
  std::uint16_t mode_bits(const DriveInputs& in, double dt) noexcept;
  void fill(const DriveInputs& in, DriveOutputs& out, double dt) noexcept;

  double decel_for(StopKind stop, const DriveInputs& in) const noexcept;
  double to_inc(double user) const noexcept { return units_.to_increments(user); }
  double to_user(double inc) const noexcept { return units_.to_user(inc); }
  // Positions: the plant and the axis work in physical increments; objects
  // read physical + home_shift_ (set by homing).
  double position_to_inc(double user) const noexcept { return units_.to_increments(user) - home_shift_; }
  double position_to_user(double physical) const noexcept { return units_.to_user(physical + home_shift_); }
  double torque_nm(double per_mille) const noexcept { return per_mille * plant_.parameters().rated_torque / 1000.0; }
  double torque_per_mille(double nm) const noexcept { return nm * 1000.0 / plant_.parameters().rated_torque; }

  // The inputs the unit scaling and the loop limits are computed from: both
  // are recomputed only when one of them changes (SDO writes), not per cycle.
  struct ScalingInputs {
    std::uint32_t encoder_increments, motor_revolutions, gear_motor_revolutions, gear_shaft_revolutions, feed,
        feed_shaft_revolutions;
    std::int16_t vl_setpoint_numerator, vl_setpoint_denominator;
    std::int32_t vl_dimension_numerator, vl_dimension_denominator;
    bool operator==(const ScalingInputs&) const = default;
  };
  struct LimitInputs {
    std::uint32_t max_motor_speed;
    std::uint16_t max_torque, positive_torque_limit, negative_torque_limit;
    bool operator==(const LimitInputs&) const = default;
  };
  // What the numeric outputs (positions, velocities, torques, following
  // error, 60FDh) are computed from; they are recomputed only when it changes
  // (a drive at rest reports the same values every cycle).
  struct OutputSources {
    double position_demand, velocity_demand, position, velocity, torque_command, torque, home_shift, increments_per_unit,
        increments_per_vl_setpoint;
    bool operator==(const OutputSources&) const = default;
  };
  struct NumericOutputs {
    std::int32_t position_demand, position_demand_internal, position_actual_internal, position_actual;
    std::int32_t velocity_demand, velocity_actual, following_error;
    std::int16_t torque_demand, torque_actual;
    std::int16_t vl_velocity_demand, vl_velocity_actual;
    std::uint32_t digital_inputs;
  };
  void update_numeric_outputs(const OutputSources& from) noexcept;

  void update_scaling(const DriveInputs& in) noexcept;
  void update_limits(const DriveInputs& in) noexcept;

  // The members every cycle reads come first, side by side, in about the
  // order step() reads them; then the parts of the plant, the axis and the
  // configuration a cycle reads (each class keeps those at its front); the
  // modes' state a CSP cycle does not read last. At 1000 drives every line
  // a drive's cycle reads is a cache miss: this order, and the alignment,
  // take the drive's lines from 20 to 14 a cycle (issue 30 item 1,
  // scripts/lines-per-drive).
  // The emergency queue's count and the interpolation buffer's flags, which
  // a cycle reads, are at the end of the one and the start of the other:
  // the two enclose the rest.
  EmcyQueue emcy_;
  Nanoseconds cycle_{-1};  // the last cycle length and its value in seconds
  double dt_ = 0;
  ScalingInputs scaling_inputs_{};
  LimitInputs limit_inputs_{};
  bool scaling_set_ = false;  // scaling_inputs_ holds what units_ came from
  bool limits_set_ = false;   // limit_inputs_ holds what limits_ came from
  bool ip_record_lost_ = false;  // a record did not fit into the buffer this cycle
  OperationMode mode_ = OperationMode::None;
  StateMachine sm_;
  ProfileGenerator gen_;
  TouchProbe probe_;
  UnitScaling units_;
  double vl_inc_per_setpoint_ = 1.0;  // vl mode: increments/s per 6042h unit (604Bh too)
  LoopDemand demand_;
  LoopLimits limits_;
  double home_shift_ = 0;  // increments
  bool homed_ = false;     // a homing completed (and none restarted since)
  std::uint16_t controlword_ = 0;
  std::uint16_t previous_controlword_ = 0;
  bool halted_ = false;
  bool stopped_ = true;
  bool stopping_ = false;  // a state-machine stop ramp is running
  bool internal_limit_ = false;
  bool warning_ = false;
  bool following_error_ = false;
  std::uint32_t latched_ = 0;
  // latched_ bit of the external fault (above the FaultKind bits).
  static constexpr std::uint32_t kExternalFaultBit = 1u << 31;
  std::optional<FaultCode> external_;
  // latched_ bit of safe torque off (DriveOverrides::safe_torque_off).
  static constexpr std::uint32_t kSafeTorqueOffBit = 1u << 30;
  DriveOverrides overrides_{};
  bool overridden_ = false;  // overrides_.any()
  std::uint16_t error_code_ = 0;
  std::uint8_t error_register_ = 0;
  Timer following_timer_, torque_timer_, position_window_, velocity_window_, speed_zero_;
  double moving_ = 0;  // increments/s below which the motor counts as standing (kMovingRpm)
  OutputSources output_sources_{};
  NumericOutputs numeric_{};
  bool numeric_set_ = false;  // numeric_ was computed from output_sources_
  IpBuffer ip_buffer_;

  DriveConfig config_;
  Plant plant_;
  Axis axis_;

  ProfilePosition pp_;
  Homing homing_;
  VelocityMode vl_;
  double vl_inc_per_unit_ = 1.0;  // vl mode: increments/s per vl unit (604Ch)
  double torque_demand_pm_ = 0;   // profile torque ramp, per mille
  // Interpolated position: the segment being interpolated (physical increments).
  double ip_from_ = 0, ip_to_ = 0, ip_elapsed_ = 0;
  bool ip_active_ = false;
};

}  // namespace ecat::ds402
