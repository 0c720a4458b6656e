#include "ds402/velocity_mode.hpp"

#include <algorithm>
#include <cmath>

namespace ecat::ds402 {

namespace {

constexpr double kMsPerS = 1000.0;
// A ramp whose remaining distance is within this share of one step's travel
// ends in that step: slopes like 0.005 units per cycle are not exact in
// binary, and the sum of n steps must not leave a 1e-15 rest for step n+1.
constexpr double kRampSnap = 1e-9;

double ratio(double num, double den) noexcept { return num != 0 && den != 0 ? num / den : 1.0; }

double slope(std::uint32_t delta_speed, std::uint16_t delta_time_s, std::uint32_t time_ms,
             std::uint32_t reference) noexcept {
  if (delta_speed != 0 && delta_time_s != 0) return static_cast<double>(delta_speed) / delta_time_s;
  if (time_ms != 0 && reference != 0) return static_cast<double>(reference) * kMsPerS / time_ms;
  return 0.0;
}

}  // namespace

double VelocityMode::setpoint_factor(const DriveInputs& in) noexcept {
  return ratio(in.vl_setpoint_numerator, in.vl_setpoint_denominator);
}

double VelocityMode::rpm_per_unit(const DriveInputs& in) noexcept {
  return 1.0 / ratio(in.vl_dimension_numerator, in.vl_dimension_denominator);
}

double VelocityMode::acceleration(const DriveInputs& in) noexcept {
  return slope(in.vl_acceleration_delta_speed, in.vl_acceleration_delta_time, in.vl_ramp_function_time,
               in.vl_velocity_reference);
}
double VelocityMode::deceleration(const DriveInputs& in) noexcept {
  return slope(in.vl_deceleration_delta_speed, in.vl_deceleration_delta_time, in.vl_slow_down_time,
               in.vl_velocity_reference);
}
double VelocityMode::quick_stop(const DriveInputs& in) noexcept {
  return slope(in.vl_quick_stop_delta_speed, in.vl_quick_stop_delta_time, in.vl_quick_stop_time,
               in.vl_velocity_reference);
}

double VelocityMode::limit(double v, const DriveInputs& in, bool& limited) noexcept {
  const double a = std::abs(v);
  limited = false;
  if (a > in.vl_max_amount) {
    limited = true;
    return std::copysign(static_cast<double>(in.vl_max_amount), v);
  }
  if (a != 0 && a < in.vl_min_amount) {
    limited = true;
    return std::copysign(static_cast<double>(in.vl_min_amount), v);
  }
  return v;
}

// One ramp step from `from` toward `to`: |v| shrinks at `dec` (through 0 when
// the sign changes, the rest of the step then grows at `acc`) and grows at
// `acc`. A slope of 0 bypasses the ramp.
double VelocityMode::step(double from, double to, double acc, double dec, double dt) noexcept {
  if (from == to) return to;
  const bool crosses = (from > 0 && to < 0) || (from < 0 && to > 0);
  const bool shrinking = crosses || std::abs(to) < std::abs(from);
  if (shrinking) {
    if (dec <= 0) return crosses ? step(0.0, to, acc, dec, dt) : to;
    const double stage = crosses ? 0.0 : to;
    const double t_needed = std::abs(from - stage) / dec;
    if (t_needed > dt * (1 + kRampSnap)) return from + std::copysign(dec * dt, stage - from);
    if (!crosses) return to;
    return step(0.0, to, acc, dec, std::max(0.0, dt - t_needed));
  }
  if (acc <= 0) return to;
  const double d = acc * dt;
  return std::abs(to - from) <= d * (1 + kRampSnap) ? to : from + std::copysign(d, to - from);
}

double VelocityMode::cycle(const DriveInputs& in, bool halted, double halt_slope, double dt) noexcept {
  bool limited = false;
  const double target = limit(static_cast<double>(in.vl_target_velocity) * setpoint_factor(in), in, limited);
  const std::uint16_t c = in.controlword;
  const double input = (c & cw_vl::kReferenceRamp) ? target : 0.0;
  limited_ = limited && (c & cw_vl::kReferenceRamp);
  if (!(c & cw_vl::kEnableRamp)) {
    output_ = 0.0;
    reached_ = input == 0.0;
  } else if (halted) {
    output_ = step(output_, 0.0, halt_slope, halt_slope, dt);
    reached_ = output_ == 0.0;
  } else if (!(c & cw_vl::kUnlockRamp)) {
    reached_ = output_ == input;
  } else {
    output_ = step(output_, input, acceleration(in), deceleration(in), dt);
    reached_ = output_ == input;
  }
  return output_;
}

}  // namespace ecat::ds402
