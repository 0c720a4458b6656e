// Drive: statusword (6041h) mode bits and the output objects.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "ds402/controlword.hpp"
#include "ds402/drive.hpp"
#include "ds402/drive_constants.hpp"
#include "ds402/statusword.hpp"

namespace ecat::ds402 {

using namespace detail;

std::uint16_t Drive::mode_bits(const DriveInputs& in, double dt) noexcept {
  const PdsState s = sm_.state();
  if (s == PdsState::QuickStopActive) return stopped_ ? sw::kTargetReached : 0;
  if (s != PdsState::OperationEnabled) return 0;
  const double pos_user = position_to_user(plant_.position());
  const double vel_user = to_user(plant_.velocity());
  const bool gen_stopped = gen_.velocity() == 0.0;
  auto position_reached = [&](double target_user, bool eligible = true) {
    return position_window_.update(eligible && std::abs(target_user - pos_user) <= in.position_window, dt,
                                   in.position_window_time / kMsPerS);
  };
  auto velocity_reached = [&](double target_user) {
    return velocity_window_.update(std::abs(target_user - vel_user) <= in.velocity_window, dt,
                                   in.velocity_window_time / kMsPerS);
  };
  const double torque_pm = torque_per_mille(plant_.torque());
  std::uint16_t b = 0;
  switch (mode_) {
    case OperationMode::ProfilePosition:
      if (pp_.acknowledge()) b |= sw::kSetPointAcknowledge;
      if (following_error_) b |= sw::kFollowingError;
      {
        const bool reached = position_reached(position_to_user(pp_.last_target()), pp_.idle());
        if (halted_ ? gen_stopped : reached) b |= sw::kTargetReached;
      }
      break;
    case OperationMode::ProfileVelocity:
      if (speed_zero_.update(std::abs(vel_user) <= in.velocity_threshold, dt, in.velocity_threshold_time / kMsPerS))
        b |= sw::kSpeedZero;
      {
        const bool reached = velocity_reached(in.target_velocity);
        if (halted_ ? gen_stopped : reached) b |= sw::kTargetReached;
      }
      break;
    case OperationMode::ProfileTorque: {
      const double target = halted_ ? 0.0 : in.target_torque;
      if (torque_demand_pm_ == target && std::abs(torque_pm - target) <= kTorqueWindowPerMille) b |= sw::kTargetReached;
      break;
    }
    case OperationMode::Homing:
      switch (homing_.status()) {
        case HomingStatus::NotStarted:
          if (!homing_.stopping()) b |= sw::kTargetReached;
          break;
        case HomingStatus::InProgress: break;
        case HomingStatus::Attained: b |= sw::kHomingAttained | sw::kTargetReached; break;
        case HomingStatus::Error:
          b |= sw::kHomingError;
          if (!homing_.stopping()) b |= sw::kTargetReached;
          break;
      }
      break;
    case OperationMode::Velocity:
      if (vl_.reached()) b |= sw::kTargetReached;  // ramp output = ramp input (0 while halted)
      break;
    case OperationMode::InterpolatedPosition:
      if (ip_active_) b |= sw::kIpModeActive;
      if (following_error_) b |= sw::kFollowingError;
      if (halted_ ? gen_stopped : position_reached(position_to_user(ip_to_), ip_active_)) b |= sw::kTargetReached;
      break;
    case OperationMode::CyclicSyncPosition:
      if (!halted_) b |= sw::kFollowsCommand;
      if (following_error_) b |= sw::kFollowingError;
      if (position_reached(static_cast<double>(in.target_position) + in.position_offset)) b |= sw::kTargetReached;
      break;
    case OperationMode::CyclicSyncVelocity:
      if (!halted_) b |= sw::kFollowsCommand;
      if (velocity_reached(static_cast<double>(in.target_velocity) + in.velocity_offset)) b |= sw::kTargetReached;
      break;
    case OperationMode::CyclicSyncTorque:
      if (!halted_) b |= sw::kFollowsCommand;
      if (std::abs(torque_pm - in.target_torque - in.torque_offset) <= kTorqueWindowPerMille) b |= sw::kTargetReached;
      break;
    default: break;
  }
  return b;
}

void Drive::fill(const DriveInputs& in, DriveOutputs& out, double dt) noexcept {
  const PdsState s = sm_.state();
  std::uint16_t status = static_cast<std::uint16_t>(state_bits(s) | sw::kRemote | mode_bits(in, dt));
  if (s != PdsState::NotReadyToSwitchOn) status |= sw::kVoltageEnabled;  // mains assumed present
  if (warning_ || emcy_.dropped() != 0 || ip_record_lost_) status |= sw::kWarning;
  // A forced limit switch (slave::FaultCatalogue's limit_switch); overridden_ first: the
  // cycle with nothing forced tests one flag.
  const bool limit_input = overridden_ && (overrides_.negative_limit || overrides_.positive_limit);
  if (internal_limit_ || plant_.torque_limited() || limit_input) status |= sw::kInternalLimitActive;
  if (homed_) status |= config_.home_found_bit;
  out.statusword = status;
  out.modes_of_operation_display = static_cast<std::int8_t>(mode_);
  const OutputSources from{demand_.position, demand_.velocity,       plant_.position(), plant_.velocity(),
                           plant_.torque_command(), plant_.torque(), home_shift_, units_.increments_per_unit(),
                           vl_inc_per_setpoint_};
  if (!numeric_set_ || !(from == output_sources_)) update_numeric_outputs(from);
  out.position_demand = numeric_.position_demand;
  out.position_demand_internal = numeric_.position_demand_internal;
  out.position_actual_internal = numeric_.position_actual_internal;
  out.position_actual = numeric_.position_actual;
  out.velocity_demand = numeric_.velocity_demand;
  out.velocity_actual = numeric_.velocity_actual;
  out.torque_demand = numeric_.torque_demand;
  out.torque_actual = numeric_.torque_actual;
  out.following_error = numeric_.following_error;
  out.error_code = error_code_;
  out.error_register = error_register_;
  out.touch_probe_status = probe_.status();
  out.touch_probe_1_positive = probe_.value(0);
  out.touch_probe_1_negative = probe_.value(1);
  out.touch_probe_2_positive = probe_.value(2);
  out.touch_probe_2_negative = probe_.value(3);
  out.digital_inputs = numeric_.digital_inputs | (overridden_ ? forced_digital_inputs() : 0);
  out.supported_drive_modes = config_.supported_modes;
  out.ip_buffer_position = ip_buffer_.ring() ? ip_buffer_.position() : in.ip_buffer_position;
  out.vl_velocity_demand = numeric_.vl_velocity_demand;
  out.vl_velocity_actual = numeric_.vl_velocity_actual;
}

void Drive::update_numeric_outputs(const OutputSources& from) noexcept {
  const double pos = from.position;
  NumericOutputs& n = numeric_;
  n.position_demand = UnitScaling::to_i32(position_to_user(from.position_demand));
  n.position_demand_internal = UnitScaling::to_i32(from.position_demand + home_shift_);
  n.position_actual_internal = UnitScaling::to_i32(pos + home_shift_);
  n.position_actual = UnitScaling::to_i32(position_to_user(pos));
  n.velocity_demand = UnitScaling::to_i32(to_user(from.velocity_demand));
  n.velocity_actual = UnitScaling::to_i32(to_user(from.velocity));
  n.vl_velocity_demand = UnitScaling::to_i16(from.velocity_demand / from.increments_per_vl_setpoint);
  n.vl_velocity_actual = UnitScaling::to_i16(from.velocity / from.increments_per_vl_setpoint);
  n.torque_demand = UnitScaling::to_i16(torque_per_mille(from.torque_command));
  n.torque_actual = UnitScaling::to_i16(torque_per_mille(from.torque));
  n.following_error = UnitScaling::to_i32(to_user(from.position_demand - pos));
  std::uint32_t di = 0;
  if (axis_.active(AxisSignal::NegativeLimit, pos)) di |= kDiNegativeLimit;
  if (axis_.active(AxisSignal::PositiveLimit, pos)) di |= kDiPositiveLimit;
  if (axis_.active(AxisSignal::HomeSwitch, pos)) di |= kDiHomeSwitch;
  if (axis_.active(AxisSignal::Probe1, pos)) di |= kDiProbe1;
  if (axis_.active(AxisSignal::Probe2, pos)) di |= kDiProbe2;
  n.digital_inputs = di;
  output_sources_ = from;
  numeric_set_ = true;
}

}  // namespace ecat::ds402
