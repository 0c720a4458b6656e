// Set-point generator shared by the profile modes, homing and the stop ramps:
// a jerk-free (trapezoidal) profile in increments, one fixed step at a time
// (CiA 402-2 §12.3 "trajectory generator", motion profile type 0 = linear ramp).
#pragma once

namespace ecat::ds402 {

class ProfileGenerator {
 public:
  void reset(double position, double velocity) noexcept {
    position_ = position;
    velocity_ = velocity;
  }
  // One step toward `target`: accelerate at `acc` up to `vmax`, brake at
  // `dec` so as to pass the target at `end_speed` (>= 0; 0 = stop on it).
  // True once at the target (at rest, or moving on at end_speed).
  bool move_to(double target, double vmax, double acc, double dec, double dt, double end_speed = 0.0) noexcept;
  // One step of a velocity ramp: |v| grows at `acc`, shrinks at `dec`.
  void ramp_velocity(double target_velocity, double acc, double dec, double dt) noexcept;
  // One step of a ramp to standstill. True once stopped.
  bool stop(double dec, double dt) noexcept {
    ramp_velocity(0.0, dec, dec, dt);
    return velocity_ == 0.0;
  }

  double position() const noexcept { return position_; }
  double velocity() const noexcept { return velocity_; }

 private:
  double position_ = 0;
  double velocity_ = 0;
};

}  // namespace ecat::ds402
