#include "ds402/drive.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "ds402/controlword.hpp"
#include "ds402/statusword.hpp"

namespace ecat::ds402 {

namespace {
constexpr std::uint32_t kFollowingErrorOff = 0xFFFFFFFF;  // 6065h all ones: no monitoring
constexpr double kMsPerS = 1000.0;
constexpr double kTorqueWindowPerMille = 10.0;  // torque "target reached" band (no object in CiA 402)
constexpr double kMovingRpm = 0.1;              // slower counts as standing still
// 60FDh bits (CiA 402-2 §8.4.12): 0 negative limit, 1 positive limit, 2 home
// switch; the probe inputs in the manufacturer part.
constexpr std::uint32_t kDiNegativeLimit = 1u << 0;
constexpr std::uint32_t kDiPositiveLimit = 1u << 1;
constexpr std::uint32_t kDiHomeSwitch = 1u << 2;
constexpr std::uint32_t kDiProbe1 = 1u << 16;
constexpr std::uint32_t kDiProbe2 = 1u << 17;
}  // namespace

Drive::Drive(DriveConfig config, const PlantParameters& plant)
    : config_(std::move(config)), plant_(plant), axis_(plant) {
  gen_.reset(plant_.position(), 0.0);
  demand_.position = plant_.position();
}

void Drive::step(const DriveInputs& in, DriveOutputs& out, Nanoseconds cycle) noexcept {
  const double dt = std::chrono::duration<double>(cycle).count();
  if (!(dt > 0)) {  // no time passed: nothing moves, report as is
    fill(in, out, 0.0);
    return;
  }
  units_ = UnitScaling::from(in, plant_.parameters().encoder_resolution);
  controlword_ = in.controlword;
  halted_ = (in.controlword & cw::kHalt) != 0;
  internal_limit_ = false;

  // Transition 15 needs the faults cleared first (CiA 402-2 §8.1.3).
  if (sm_.fault_reset_edge(in.controlword) && sm_.state() == PdsState::Fault) clear_faults();

  StateMachine::Inputs si;
  si.controlword = in.controlword;
  si.fault = latched_ != 0;
  si.motion_stopped = stopped_;
  si.quick_stop_option = config_.quick_stop.pick(in.quick_stop_option);
  si.shutdown_option = config_.shutdown.pick(in.shutdown_option);
  si.disable_operation_option = config_.disable_operation.pick(in.disable_operation_option);
  si.fault_reaction_option = config_.fault_reaction.pick(in.fault_reaction_option);
  const PdsState before = sm_.state();
  sm_.step(si);
  if (sm_.state() == PdsState::OperationEnabled && before != PdsState::OperationEnabled) enter_mode();

  select_mode(in);

  if (sm_.stop() == StopKind::None) stopping_ = false;
  if (!sm_.power_stage_on()) {
    demand_ = LoopDemand{};
    demand_.position = plant_.position();
    gen_.reset(plant_.position(), plant_.velocity());
    stopped_ = true;
  } else if (sm_.stop() != StopKind::None) {
    // A stop ramps down from the motion as it is, whatever the mode demanded.
    if (!stopping_) gen_.reset(plant_.position(), plant_.velocity());
    stopping_ = true;
    run_stop(sm_.stop(), in, dt);
  } else {
    run_mode(in, dt);
  }

  const PlantParameters& pp = plant_.parameters();
  const double max_rpm = in.max_motor_speed ? static_cast<double>(in.max_motor_speed) : pp.max_speed;
  limits_.velocity = plant_.rpm_to_increments(max_rpm);
  limits_.torque_positive = std::min(pp.peak_torque, torque_nm(std::min(in.max_torque, in.positive_torque_limit)));
  limits_.torque_negative = std::min(pp.peak_torque, torque_nm(std::min(in.max_torque, in.negative_torque_limit)));
  plant_.step(demand_, limits_, dt);

  probe_.cycle(in.touch_probe_function, axis_, plant_.previous_position(), plant_.position(), units_, home_shift_);
  monitor(in, dt);
  fill(in, out, dt);
  previous_controlword_ = in.controlword;
}

void Drive::select_mode(const DriveInputs& in) noexcept {
  const std::int8_t req = in.modes_of_operation;
  if (req == static_cast<std::int8_t>(mode_)) {
    warning_ = false;
    return;
  }
  if (req != 0 && !config_.supports_mode(req)) {
    warning_ = true;  // not taken: 6061h keeps showing the mode in use
    return;
  }
  warning_ = false;
  mode_ = static_cast<OperationMode>(req);
  if (sm_.state() == PdsState::OperationEnabled) enter_mode();
}

// A new mode (or enabling) starts from where the motor is.
void Drive::enter_mode() noexcept {
  if (homing_.active()) homing_.interrupt();
  gen_.reset(plant_.position(), plant_.velocity());
  pp_.enter(plant_.position());
  torque_demand_pm_ = torque_per_mille(plant_.torque());
  position_window_ = velocity_window_ = speed_zero_ = Timer{};
  demand_.position = plant_.position();
  ip_active_ = false;
}

double Drive::decel_for(StopKind stop, const DriveInputs& in) const noexcept {
  const PlantParameters& p = plant_.parameters();
  // Deceleration at the torque limit (CiA 402-2 "current limit" stop).
  const double at_limit = std::min(limits_.torque_positive, limits_.torque_negative) / p.total_inertia() *
                          p.encoder_resolution / (2.0 * 3.14159265358979323846);
  double d = 0;
  switch (stop) {
    case StopKind::SlowDownRamp: d = to_inc(in.profile_deceleration); break;
    case StopKind::QuickStopRamp: d = to_inc(in.quick_stop_deceleration); break;
    default: d = at_limit; break;
  }
  return d > 0 ? d : at_limit;  // a zero ramp would never stop
}

void Drive::run_stop(StopKind stop, const DriveInputs& in, double dt) noexcept {
  // Stopped once the ramp has ended and the motor follows it to rest.
  stopped_ = gen_.stop(decel_for(stop, in), dt) &&
             std::abs(plant_.velocity()) < plant_.rpm_to_increments(kMovingRpm);
  demand_ = LoopDemand{LoopDemand::Kind::Position, gen_.position(), gen_.velocity(), 0, 0};
}

void Drive::hold() noexcept {
  gen_.reset(gen_.position(), 0.0);
  demand_ = LoopDemand{LoopDemand::Kind::Position, gen_.position(), 0, 0, 0};
}

void Drive::run_mode(const DriveInputs& in, double dt) noexcept {
  using Kind = LoopDemand::Kind;
  stopped_ = false;
  const double halt_decel = decel_for(stop_for_halt(config_.halt.pick(in.halt_option)), in);
  const bool limits_on = in.software_limit_min < in.software_limit_max;
  const double lim_min = position_to_inc(in.software_limit_min), lim_max = position_to_inc(in.software_limit_max);
  const double vmax_profile = to_inc(in.max_profile_velocity);
  const double actual = plant_.position();

  switch (mode_) {
    case OperationMode::ProfilePosition: {
      PpSetPoint sp{to_inc(in.target_position) - ((in.controlword & cw::kRelative) ? 0.0 : home_shift_), std::min(to_inc(in.profile_velocity), vmax_profile),
                    to_inc(in.profile_acceleration), to_inc(in.profile_deceleration)};
      pp_.handshake(in.controlword, sp, (in.controlword & cw::kRelative) != 0, limits_on ? lim_min : 0,
                    limits_on ? lim_max : 0);
      internal_limit_ = pp_.target_clipped();
      if (halted_) {
        gen_.stop(halt_decel, dt);
      } else {
        pp_.move(gen_, dt);
      }
      demand_ = LoopDemand{Kind::Position, gen_.position(), gen_.velocity(), 0, 0};
      return;
    }
    case OperationMode::ProfileVelocity: {
      const double target = std::clamp(to_inc(in.target_velocity), -vmax_profile, vmax_profile);
      if (halted_) {
        gen_.ramp_velocity(0.0, halt_decel, halt_decel, dt);
      } else {
        gen_.ramp_velocity(target, to_inc(in.profile_acceleration), to_inc(in.profile_deceleration), dt);
      }
      demand_ = LoopDemand{Kind::Velocity, actual, gen_.velocity(), 0, 0};
      return;
    }
    case OperationMode::ProfileTorque: {
      const double target = halted_ ? 0.0 : in.target_torque;
      const double step = static_cast<double>(in.torque_slope) * dt;
      torque_demand_pm_ += std::clamp(target - torque_demand_pm_, -step, step);
      gen_.reset(actual, plant_.velocity());
      demand_ = LoopDemand{Kind::Torque, actual, 0, torque_nm(torque_demand_pm_), 0};
      return;
    }
    case OperationMode::Homing: {
      const bool start = in.controlword & cw::kHomingStart;
      if (start && !(previous_controlword_ & cw::kHomingStart) && !homing_.active()) {
        homing_.start(config_.supports_homing(in.homing_method) ? in.homing_method : std::int8_t{0}, axis_,
                      actual);
      } else if ((!start || halted_) && homing_.active()) {
        homing_.interrupt();
      }
      const Homing::Speeds speeds{to_inc(in.homing_speed_switch), to_inc(in.homing_speed_zero),
                                  to_inc(in.homing_acceleration)};
      if (const auto shift = homing_.cycle(gen_, axis_, plant_.previous_position(), actual, speeds,
                                           to_inc(in.home_offset), dt)) {
        home_shift_ = *shift;
      }
      demand_ = LoopDemand{Kind::Position, gen_.position(), gen_.velocity(), 0, 0};
      return;
    }
    case OperationMode::InterpolatedPosition:
      run_interpolated(in, dt);
      return;
    case OperationMode::CyclicSyncPosition: {
      if (halted_) {
        gen_.stop(halt_decel, dt);
        demand_ = LoopDemand{Kind::Position, gen_.position(), gen_.velocity(), 0, 0};
        return;
      }
      double target = position_to_inc(static_cast<double>(in.target_position) + in.position_offset);
      if (limits_on && (target < lim_min || target > lim_max)) {
        target = std::clamp(target, lim_min, lim_max);
        internal_limit_ = true;
      }
      const double v = (target - demand_.position) / dt;
      gen_.reset(target, v);
      demand_ = LoopDemand{Kind::Position, target, v, torque_nm(in.torque_offset), to_inc(in.velocity_offset)};
      return;
    }
    case OperationMode::CyclicSyncVelocity: {
      if (halted_) {
        gen_.stop(halt_decel, dt);
        demand_ = LoopDemand{Kind::Position, gen_.position(), gen_.velocity(), 0, 0};
        return;
      }
      gen_.reset(actual, plant_.velocity());
      demand_ = LoopDemand{Kind::Velocity, actual, to_inc(static_cast<double>(in.target_velocity) + in.velocity_offset),
                           torque_nm(in.torque_offset), 0};
      return;
    }
    case OperationMode::CyclicSyncTorque: {
      if (halted_) {
        gen_.stop(halt_decel, dt);
        demand_ = LoopDemand{Kind::Position, gen_.position(), gen_.velocity(), 0, 0};
        return;
      }
      gen_.reset(actual, plant_.velocity());
      demand_ = LoopDemand{Kind::Torque, actual, 0,
                           torque_nm(static_cast<double>(in.target_torque) + in.torque_offset), 0};
      return;
    }
    default:
      hold();  // no mode, or one this simulator does not run (vl)
      return;
  }
}

// Interpolated position (CiA 402-2 §13, sub-mode 0 linear): while bit 4 is
// set, every interpolation period 60C2h takes 60C1h:01 as the next point and
// the demand moves to it in a straight line over that period.
void Drive::run_interpolated(const DriveInputs& in, double dt) noexcept {
  const bool enable = (in.controlword & cw::kEnableIpMode) != 0;
  if (!enable || halted_) {
    ip_active_ = false;
    if (halted_) {
      gen_.stop(decel_for(stop_for_halt(config_.halt.pick(in.halt_option)), in), dt);
    } else {
      gen_.reset(gen_.position(), 0.0);
    }
    demand_ = LoopDemand{LoopDemand::Kind::Position, gen_.position(), gen_.velocity(), 0, 0};
    return;
  }
  const double period = in.ip_period_value == 0
                            ? dt
                            : in.ip_period_value * std::pow(10.0, std::clamp<int>(in.ip_period_index, -9, 0));
  if (!ip_active_ || ip_elapsed_ >= period - 1e-12) {
    ip_from_ = ip_active_ ? ip_to_ : gen_.position();
    ip_to_ = position_to_inc(in.ip_position);
    ip_elapsed_ = 0;
    ip_active_ = true;
  }
  ip_elapsed_ += dt;
  const double share = std::min(1.0, ip_elapsed_ / period);
  const double target = ip_from_ + (ip_to_ - ip_from_) * share;
  const double v = (target - demand_.position) / dt;
  gen_.reset(target, v);
  demand_ = LoopDemand{LoopDemand::Kind::Position, target, v, 0, 0};
}

void Drive::raise_fault(FaultKind k) noexcept {
  const std::uint32_t bit = 1u << static_cast<unsigned>(k);
  if (latched_ & bit) return;
  latched_ |= bit;
  const FaultCode code = config_.fault_codes[static_cast<std::size_t>(k)];
  error_code_ = code.error_code;
  error_register_ = static_cast<std::uint8_t>(error_register_ | error_register::kGeneric | code.error_register);
  EmcyRequest r;
  r.error_code = config_.emcy_code.value_or(code.error_code);
  r.error_register = error_register_;
  if (config_.emcy_code) {  // alarm number in EMCY bytes 4-5
    r.manufacturer[1] = static_cast<std::uint8_t>(code.error_code);
    r.manufacturer[2] = static_cast<std::uint8_t>(code.error_code >> 8);
  }
  emcy_.push(r);
}

void Drive::clear_faults() noexcept {
  latched_ = 0;
  error_code_ = 0;
  error_register_ = 0;
  following_error_ = false;
  following_timer_ = torque_timer_ = Timer{};
  emcy_.push(EmcyRequest{kEmcyErrorReset, 0, {}});
}

void Drive::monitor(const DriveInputs& in, double dt) noexcept {
  const PlantParameters& p = plant_.parameters();
  const bool driving = sm_.power_stage_on();
  const bool operating = sm_.operation_active();
  const double pos = plant_.position();
  const double v = plant_.velocity();
  const double moving = plant_.rpm_to_increments(kMovingRpm);

  // Following error (6065h/6066h, CiA 402-2 §12.4.2).
  if (driving && demand_.kind == LoopDemand::Kind::Position && in.following_error_window != kFollowingErrorOff) {
    const double error = std::abs(to_user(demand_.position - pos));
    following_error_ = following_timer_.update(error > in.following_error_window, dt,
                                               in.following_error_timeout / kMsPerS);
    if (following_error_) raise_fault(FaultKind::FollowingError);
  } else {
    following_error_ = false;
    following_timer_ = Timer{};
  }
  // Hardware limit switches, outside homing: moving into one is a fault.
  if (operating && mode_ != OperationMode::Homing) {
    if (axis_.active(AxisSignal::PositiveLimit, pos) && v > moving) raise_fault(FaultKind::PositiveLimitSwitch);
    if (axis_.active(AxisSignal::NegativeLimit, pos) && v < -moving) raise_fault(FaultKind::NegativeLimitSwitch);
  }
  // Software limits (607Dh) in the modes that do not clip their targets.
  const bool clipping = mode_ == OperationMode::ProfilePosition || mode_ == OperationMode::Homing ||
                        mode_ == OperationMode::CyclicSyncPosition ||
                        mode_ == OperationMode::InterpolatedPosition;
  if (operating && !clipping && in.software_limit_min < in.software_limit_max) {
    const double u = position_to_user(pos);
    if ((u > in.software_limit_max && v > moving) || (u < in.software_limit_min && v < -moving)) {
      raise_fault(FaultKind::SoftwareLimit);
    }
  }
  if (std::abs(plant_.increments_to_rpm(v)) > p.over_speed) raise_fault(FaultKind::OverSpeed);
  if (torque_timer_.update(driving && plant_.torque_limited(), dt, p.over_torque_time)) {
    raise_fault(FaultKind::OverTorque);
  }
  if (in.sync_lost && driving) raise_fault(FaultKind::SyncLost);
}

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
  if (warning_ || emcy_.dropped() != 0) status |= sw::kWarning;
  if (internal_limit_ || plant_.torque_limited()) status |= sw::kInternalLimitActive;
  out.statusword = status;
  out.modes_of_operation_display = static_cast<std::int8_t>(mode_);
  const double pos = plant_.position();
  out.position_demand = UnitScaling::to_i32(position_to_user(demand_.position));
  out.position_demand_internal = UnitScaling::to_i32(demand_.position + home_shift_);
  out.position_actual_internal = UnitScaling::to_i32(pos + home_shift_);
  out.position_actual = UnitScaling::to_i32(position_to_user(pos));
  out.velocity_demand = UnitScaling::to_i32(to_user(demand_.velocity));
  out.velocity_actual = UnitScaling::to_i32(to_user(plant_.velocity()));
  out.torque_demand = UnitScaling::to_i16(torque_per_mille(plant_.torque_command()));
  out.torque_actual = UnitScaling::to_i16(torque_per_mille(plant_.torque()));
  out.following_error = UnitScaling::to_i32(to_user(demand_.position - pos));
  out.error_code = error_code_;
  out.error_register = error_register_;
  out.touch_probe_status = probe_.status();
  out.touch_probe_1_positive = probe_.value(0);
  out.touch_probe_1_negative = probe_.value(1);
  out.touch_probe_2_positive = probe_.value(2);
  out.touch_probe_2_negative = probe_.value(3);
  std::uint32_t di = 0;
  if (axis_.active(AxisSignal::NegativeLimit, pos)) di |= kDiNegativeLimit;
  if (axis_.active(AxisSignal::PositiveLimit, pos)) di |= kDiPositiveLimit;
  if (axis_.active(AxisSignal::HomeSwitch, pos)) di |= kDiHomeSwitch;
  if (axis_.active(AxisSignal::Probe1, pos)) di |= kDiProbe1;
  if (axis_.active(AxisSignal::Probe2, pos)) di |= kDiProbe2;
  out.digital_inputs = di;
  out.supported_drive_modes = config_.supported_modes;
}

}  // namespace ecat::ds402
