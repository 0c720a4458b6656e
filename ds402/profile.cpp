#include "ds402/profile.hpp"

#include <algorithm>
#include <cmath>

namespace ecat::ds402 {

namespace {
// A target closer than this many dec·dt² is reached in the next step: the
// braking curve cannot resolve it any finer (see move_to).
constexpr double kSnapSteps = 1.5;
}  // namespace

bool ProfileGenerator::move_to(double target, double vmax, double acc, double dec, double dt,
                               double end_speed) noexcept {
  const double rem = target - position_;
  if (rem == 0.0 && velocity_ == 0.0) return true;
  const double dir = rem > 0 ? 1.0 : (rem < 0 ? -1.0 : (velocity_ > 0 ? -1.0 : 1.0));
  const double dist = std::abs(rem);
  const double toward = velocity_ * dir;  // speed toward the target (negative: moving away)
  double next;
  if (toward < 0) {
    next = std::min(toward + dec * dt, 0.0);  // brake the wrong-way motion first
  } else {
    if (end_speed > 0 && toward * dt >= dist) {  // passes the target this step: hand over
      position_ = target;
      velocity_ = std::min(toward, end_speed) * dir;
      return true;
    }
    if (end_speed <= 0 && dist <= kSnapSteps * dec * dt * dt && toward <= 2.0 * dec * dt) {
      position_ = target;
      velocity_ = 0.0;
      return true;
    }
    next = toward > vmax ? std::max(toward - dec * dt, vmax) : std::min(toward + acc * dt, vmax);
    // Largest speed from which braking at `dec` still reaches the target at
    // end_speed after this step: v·dt + (v² - end²)/(2·dec) = dist.
    const double brake = -dec * dt + std::sqrt(dec * dt * dec * dt + 2.0 * dec * dist + end_speed * end_speed);
    next = std::min(next, brake);
    next = std::max(next, toward - dec * dt);  // cannot brake harder than dec (may overshoot)
  }
  velocity_ = next * dir;
  position_ += velocity_ * dt;
  return false;
}

void ProfileGenerator::ramp_velocity(double target_velocity, double acc, double dec, double dt) noexcept {
  const double diff = target_velocity - velocity_;
  if (diff == 0.0) {
    position_ += velocity_ * dt;
    return;
  }
  // Growing in magnitude (same sign as the present velocity, or from rest): acc.
  const bool speeding_up = velocity_ == 0.0 || (velocity_ > 0) == (diff > 0);
  const double rate = (speeding_up ? acc : dec) * dt;
  velocity_ += std::clamp(diff, -rate, rate);
  position_ += velocity_ * dt;
}

}  // namespace ecat::ds402
