// Profile position mode (CiA 402-2 §12): the new-set-point / set-point
// acknowledge handshake (controlword bit 4, statusword bit 12), "change set
// immediately" (bit 5), absolute/relative targets (bit 6), a one-deep
// set-point buffer, "change on set-point" (bit 9: pass the first target
// without stopping when the next move goes on in the same direction) and a
// trapezoidal move with 6081h/6083h/6084h.
#pragma once

#include <cstdint>
#include <optional>

#include "ds402/profile.hpp"

namespace ecat::ds402 {

struct PpSetPoint {
  double target = 0;        // increments
  double velocity = 0;      // increments/s
  double acceleration = 0;  // increments/s²
  double deceleration = 0;  // increments/s²
};

class ProfilePosition {
 public:
  // Mode entry (or enable): no set-point, relative targets count from `base`.
  void enter(double base) noexcept;

  // The handshake: `setpoint` holds the objects as they are this cycle (its
  // target already absolute or relative as bit 6 says: relative ones are
  // added to the last accepted target here). Software position limits
  // [min, max] (increments; min >= max: none) clip the target.
  void handshake(std::uint16_t controlword, PpSetPoint setpoint, bool relative, double min, double max) noexcept;
  // One motion step (not while halted).
  void move(ProfileGenerator& gen, double dt) noexcept;

  bool acknowledge() const noexcept { return acknowledge_; }
  // No set-point in progress or buffered.
  bool idle() const noexcept { return !active_ && !buffered_; }
  double last_target() const noexcept { return last_target_; }
  bool target_clipped() const noexcept { return clipped_; }

 private:
  std::optional<PpSetPoint> active_;
  std::optional<PpSetPoint> buffered_;
  double last_target_ = 0;
  bool previous_new_setpoint_ = false;
  bool change_on_setpoint_ = false;
  bool acknowledge_ = false;
  bool clipped_ = false;
};

}  // namespace ecat::ds402
