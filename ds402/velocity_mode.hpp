// Velocity mode "vl" (CiA 402-2 / IEC 61800-7-201, velocity mode): the
// set-point chain 6042h -> set-point factor 604Bh -> velocity limit function
// 6046h -> ramp function 6048h/6049h (604Fh/6050h) -> 6043h, and the
// controlword bits 4-6 that act on the ramp. Velocities are "vl units"
// (rpm scaled by the dimension factor 604Ch); the ramp works after the
// set-point factor. docs/ds402.md "vl mode" has the choices made.
#pragma once

#include <cstdint>

#include "ds402/objects.hpp"

namespace ecat::ds402 {

// Controlword bits of vl mode (CiA 402-2, vl controlword).
namespace cw_vl {
inline constexpr std::uint16_t kEnableRamp = 1u << 4;     // 0: ramp output forced to 0
inline constexpr std::uint16_t kUnlockRamp = 1u << 5;     // 0: ramp output held at its value
inline constexpr std::uint16_t kReferenceRamp = 1u << 6;  // 0: ramp input set to 0
}  // namespace cw_vl

class VelocityMode {
 public:
  // Set-point factor 604Bh (numerator/denominator; 0 in either: 1).
  static double setpoint_factor(const DriveInputs& in) noexcept;
  // rpm per vl unit from the dimension factor 604Ch: a vl unit is the rpm
  // value times 604Ch:01/604Ch:02 (0 in either: 1).
  static double rpm_per_unit(const DriveInputs& in) noexcept;
  // Slopes in vl units per second: 6048h/6049h/604Ah (delta speed / delta
  // time). When that object's delta speed or delta time is 0, the time
  // objects 604Fh/6050h/6051h (ms from 0 to 604Eh) give it; 0 when neither
  // is set (then the ramp is bypassed, and a stop uses the torque limit).
  static double acceleration(const DriveInputs& in) noexcept;
  static double deceleration(const DriveInputs& in) noexcept;
  static double quick_stop(const DriveInputs& in) noexcept;

  // The velocity limit function (6046h): |v| above the max amount is cut to
  // it, a non-zero |v| below the min amount raised to it; 0 stays 0.
  // `limited` tells whether it acted.
  static double limit(double v, const DriveInputs& in, bool& limited) noexcept;

  // Starts from the present motion (vl units).
  void enter(double output) noexcept { output_ = output; }
  // One cycle of the ramp function. `halt_slope` (vl units/s, > 0) is the
  // 605Dh ramp while halted. Returns the ramp output (vl units).
  double cycle(const DriveInputs& in, bool halted, double halt_slope, double dt) noexcept;

  double output() const noexcept { return output_; }
  bool limited() const noexcept { return limited_; }
  // The ramp output equals its input (the input being 0 while halted).
  bool reached() const noexcept { return reached_; }

 private:
  static double step(double from, double to, double acc, double dec, double dt) noexcept;
  double output_ = 0;
  bool limited_ = false;
  bool reached_ = false;
};

}  // namespace ecat::ds402
