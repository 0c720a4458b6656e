#include "ds402/profile_position.hpp"

#include <algorithm>

#include "ds402/controlword.hpp"

namespace ecat::ds402 {

void ProfilePosition::enter(double base) noexcept {
  active_.reset();
  buffered_.reset();
  last_target_ = base;
  acknowledge_ = false;
  clipped_ = false;
  // A bit 4 already set on entry is not a new set-point: it needs an edge.
  previous_new_setpoint_ = true;
}

void ProfilePosition::handshake(std::uint16_t controlword, PpSetPoint sp, bool relative, double min,
                                double max) noexcept {
  const bool new_setpoint = controlword & cw::kNewSetPoint;
  change_on_setpoint_ = (controlword & cw::kChangeOnSetPoint) != 0;
  if (new_setpoint && !previous_new_setpoint_) {
    if (relative) sp.target += last_target_;
    clipped_ = false;
    if (min < max && (sp.target < min || sp.target > max)) {
      sp.target = std::clamp(sp.target, min, max);
      clipped_ = true;
    }
    bool accepted = true;
    if ((controlword & cw::kChangeSetImmediately) || !active_) {
      active_ = sp;  // replaces the move in progress (and drops the buffer)
      buffered_.reset();
    } else if (!buffered_) {
      buffered_ = sp;
    } else {
      accepted = false;  // buffer full: ignored, not acknowledged
    }
    if (accepted) {
      last_target_ = sp.target;
      acknowledge_ = true;
    }
  }
  previous_new_setpoint_ = new_setpoint;
  // Acknowledge drops once the master released bit 4 and the buffer can
  // take another set-point.
  if (!new_setpoint && !buffered_) acknowledge_ = false;
}

void ProfilePosition::move(ProfileGenerator& gen, double dt) noexcept {
  if (!active_) {
    gen.reset(gen.position(), 0.0);  // hold where the last move ended
    (void)dt;
    return;
  }
  const PpSetPoint& a = *active_;
  // Bit 9: carry the speed through the first target when the buffered move
  // continues the same way (at the lower of the two profile velocities).
  double end_speed = 0;
  if (change_on_setpoint_ && buffered_) {
    const double here_to_first = a.target - gen.position();
    const double first_to_next = buffered_->target - a.target;
    if (here_to_first * first_to_next > 0) end_speed = std::min(a.velocity, buffered_->velocity);
  }
  if (gen.move_to(a.target, a.velocity, a.acceleration, a.deceleration, dt, end_speed)) {
    active_ = buffered_;  // the buffered set-point starts when the first one is done
    buffered_.reset();
  }
}

}  // namespace ecat::ds402
