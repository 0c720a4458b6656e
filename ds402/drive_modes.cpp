// Drive: set-point generation per mode of operation and the stop ramps
// (CiA 402-2 §10-§15).
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

double Drive::decel_for(StopKind stop, const DriveInputs& in) const noexcept {
  const PlantParameters& p = plant_.parameters();
  // Deceleration at the torque limit (CiA 402-2 "current limit" stop).
  const double at_limit = std::min(limits_.torque_positive, limits_.torque_negative) / p.total_inertia() *
                          p.encoder_resolution / (2.0 * 3.14159265358979323846);
  double d = 0;
  const bool vl = mode_ == OperationMode::Velocity;  // vl has its own ramps (6049h, 604Ah)
  switch (stop) {
    case StopKind::SlowDownRamp:
      d = vl ? VelocityMode::deceleration(in) * vl_inc_per_unit_ : to_inc(in.profile_deceleration);
      break;
    case StopKind::QuickStopRamp:
      d = vl ? VelocityMode::quick_stop(in) * vl_inc_per_unit_ : to_inc(in.quick_stop_deceleration);
      break;
    default: d = at_limit; break;
  }
  return d > 0 ? d : at_limit;  // a zero ramp would never stop
}

void Drive::run_stop(StopKind stop, const DriveInputs& in, double dt) noexcept {
  // Stopped once the ramp has ended and the motor follows it to rest.
  stopped_ = gen_.stop(decel_for(stop, in), dt) &&
             std::abs(plant_.velocity()) < moving_;
  demand_ = LoopDemand{LoopDemand::Kind::Position, gen_.position(), gen_.velocity(), 0, 0};
}

void Drive::hold() noexcept {
  gen_.reset(gen_.position(), 0.0);
  demand_ = LoopDemand{LoopDemand::Kind::Position, gen_.position(), 0, 0, 0};
}

void Drive::run_mode(const DriveInputs& in, double dt) noexcept {
  using Kind = LoopDemand::Kind;
  stopped_ = false;
  // Only a halted mode ramps with it.
  auto halt_decel = [&] { return decel_for(stop_for_halt(config_.halt.pick(in.halt_option)), in); };
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
        gen_.stop(halt_decel(), dt);
      } else {
        pp_.move(gen_, dt);
      }
      demand_ = LoopDemand{Kind::Position, gen_.position(), gen_.velocity(), 0, 0};
      return;
    }
    case OperationMode::ProfileVelocity: {
      const double target = std::clamp(to_inc(in.target_velocity), -vmax_profile, vmax_profile);
      if (halted_) {
        {
          const double d = halt_decel();
          gen_.ramp_velocity(0.0, d, d, dt);
        }
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
        homed_ = false;
        homing_.start(config_.supports_homing(in.homing_method) ? in.homing_method : std::int8_t{0}, axis_,
                      actual);
      } else if ((!start || halted_) && homing_.active()) {
        homing_.interrupt();
      }
      const Homing::Speeds speeds{to_inc(in.homing_speed_switch), to_inc(in.homing_speed_zero),
                                  to_inc(in.homing_acceleration)};
      const Homing::Current current{plant_.torque() / plant_.parameters().torque_constant * kMaPerA,
                                    static_cast<double>(in.homing_current_threshold)};
      if (const auto shift = homing_.cycle(gen_, axis_, plant_.previous_position(), actual, speeds,
                                           to_inc(in.home_offset), dt, current)) {
        home_shift_ = *shift;
        homed_ = true;
      }
      demand_ = LoopDemand{Kind::Position, gen_.position(), gen_.velocity(), 0, 0};
      return;
    }
    case OperationMode::Velocity: {
      const double halt_slope = halted_ ? halt_decel() / vl_inc_per_unit_ : 0.0;
      const double v = vl_.cycle(in, halted_, halt_slope, dt) * vl_inc_per_unit_;
      internal_limit_ = vl_.limited();
      gen_.reset(actual, v);
      demand_ = LoopDemand{Kind::Velocity, actual, v, 0, 0};
      return;
    }
    case OperationMode::InterpolatedPosition:
      run_interpolated(in, dt);
      return;
    case OperationMode::CyclicSyncPosition: {
      if (halted_) {
        gen_.stop(halt_decel(), dt);
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
        gen_.stop(halt_decel(), dt);
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
        gen_.stop(halt_decel(), dt);
        demand_ = LoopDemand{Kind::Position, gen_.position(), gen_.velocity(), 0, 0};
        return;
      }
      gen_.reset(actual, plant_.velocity());
      demand_ = LoopDemand{Kind::Torque, actual, 0,
                           torque_nm(static_cast<double>(in.target_torque) + in.torque_offset), 0};
      return;
    }
    default:
      hold();  // no mode
      return;
  }
}

// Interpolated position (CiA 402-2 §13, sub-mode 0 linear): while bit 4 is
// set, every interpolation period 60C2h takes the next point - 60C1h:01, or
// with the buffer enabled (60C4h:06 = 1) the next buffered record - and the
// demand moves to it in a straight line over that period.
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
    if (!ip_buffer_.enabled()) {
      ip_to_ = position_to_inc(in.ip_position);
    } else if (const auto record = ip_buffer_.pop()) {
      ip_to_ = position_to_inc(*record);  // 60C4h: the next buffered record
    } else {
      ip_to_ = ip_from_;  // buffer empty: hold the last point
    }
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

}  // namespace ecat::ds402
