// Factor group (CiA 402-2 §6.3.3, objects 608Fh, 6091h, 6092h): user
// position units <-> encoder increments. Velocities are position units per
// second and accelerations position units per s² (the profile's defaults).
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "ds402/objects.hpp"

namespace ecat::ds402 {

class UnitScaling {
 public:
  UnitScaling() = default;
  // `encoder_resolution` is the plant's increments per motor revolution, used
  // when 608Fh:01 is 0.
  static UnitScaling from(const DriveInputs& in, std::uint32_t encoder_resolution) noexcept {
    UnitScaling s;
    if (in.feed == 0 || in.feed_shaft_revolutions == 0) return s;  // 1 unit = 1 increment
    const double enc = in.encoder_increments ? in.encoder_increments : encoder_resolution;
    const double motor_revs = in.motor_revolutions ? in.motor_revolutions : 1;
    const double gear = in.gear_shaft_revolutions
                            ? static_cast<double>(in.gear_motor_revolutions) / in.gear_shaft_revolutions
                            : 1.0;
    const double feed_per_shaft_rev = static_cast<double>(in.feed) / in.feed_shaft_revolutions;
    const double f = enc / motor_revs * gear / feed_per_shaft_rev;
    if (std::isfinite(f) && f > 0) s.inc_per_unit_ = f;  // a zero gear keeps 1:1
    return s;
  }

  double increments_per_unit() const noexcept { return inc_per_unit_; }
  double to_increments(double user) const noexcept { return user * inc_per_unit_; }
  double to_user(double increments) const noexcept { return increments / inc_per_unit_; }

  // Rounded half away from zero (as std::round) and saturated to the object
  // types; NaN gives 0. Inline, without the libm call: in range the value
  // truncates to an integer t exactly, v - t is exact, and the half decides.
  // tests/ds402/units_test.cpp checks both against std::round.
  static std::int32_t to_i32(double v) noexcept { return to_integer<std::int32_t>(v); }
  static std::int16_t to_i16(double v) noexcept { return to_integer<std::int16_t>(v); }

 private:
  template <typename T>
  static T to_integer(double v) noexcept {
    // Values at or past these round to the type's end (exact in a double).
    constexpr double kRoundsToMax = static_cast<double>(std::numeric_limits<T>::max()) - 0.5;
    constexpr double kRoundsToMin = static_cast<double>(std::numeric_limits<T>::min()) + 0.5;
    if (std::abs(v) < kRoundsToMax) return static_cast<T>(round_in_range(v));  // NaN: false
    if (v >= kRoundsToMax) return std::numeric_limits<T>::max();
    if (v <= kRoundsToMin) return std::numeric_limits<T>::min();
    if (v != v) return 0;  // NaN
    return static_cast<T>(round_in_range(v));  // (min + 0.5, min + 1.5]: min + 1
  }
  // |v| < 2^31: truncates to t exactly; v - t is exact.
  static std::int64_t round_in_range(double v) noexcept {
    const auto t = static_cast<std::int64_t>(v);
    const double frac = v - static_cast<double>(t);
    return t + (frac >= 0.5) - (frac <= -0.5);
  }

  double inc_per_unit_ = 1.0;
};

}  // namespace ecat::ds402
