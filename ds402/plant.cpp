#include "ds402/plant.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ecat::ds402 {

namespace {
constexpr double kTwoPi = 2.0 * std::numbers::pi;
// Integral zero of the velocity PI at a quarter of the loop bandwidth: about
// 50° phase margin with the current-loop lag (a common servo tuning rule).
constexpr double kIntegralZeroRatio = 0.25;
constexpr double kStandstill = 1e-9;  // rad/s below which the rotor counts as stopped

double sign(double v) noexcept { return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0); }
}  // namespace

Plant::Plant(const PlantParameters& p) noexcept
    : p_(p), rad_per_inc_(kTwoPi / static_cast<double>(p.encoder_resolution)) {
  const double wc = kTwoPi * p_.velocity_bandwidth;
  kv_ = p_.total_inertia() * wc * rad_per_inc_;
  ki_ = kv_ * wc * kIntegralZeroRatio;
  position_ = previous_position_ = last_position_ref_ = p_.initial_position;
}

void Plant::step(const LoopDemand& demand, const LoopLimits& limits, double dt) noexcept {
  previous_position_ = position_;
  const bool position_mode = demand.kind == LoopDemand::Kind::Position;
  const double start_ref = (position_mode && last_was_position_) ? last_position_ref_ : demand.position;
  const int n = std::max(1, static_cast<int>(std::ceil(dt / p_.sub_step - 1e-9)));
  const double h = dt / n;
  torque_limited_ = false;
  for (int i = 1; i <= n; ++i) {
    const double ref = start_ref + (demand.position - start_ref) * static_cast<double>(i) / n;
    sub_step(demand, limits, ref, h);
  }
  last_was_position_ = position_mode;
  last_position_ref_ = demand.position;
}

void Plant::sub_step(const LoopDemand& d, const LoopLimits& lim, double position_ref, double h) noexcept {
  using Kind = LoopDemand::Kind;
  double tc = 0;
  if (d.kind == Kind::Off) {
    integral_ = 0;
  } else if (d.kind == Kind::Torque) {
    integral_ = 0;
    // Speed limitation in torque modes: the torque may not drive the motor
    // beyond the velocity limit.
    const double upper = kv_ * (lim.velocity - velocity_);
    const double lower = kv_ * (-lim.velocity - velocity_);
    tc = std::clamp(d.torque, std::min(lower, upper), std::max(lower, upper));
  } else {
    double vcmd = d.velocity + d.velocity_offset;
    if (d.kind == Kind::Position) {
      vcmd = p_.position_gain * (position_ref - position_) + p_.velocity_feed_forward * d.velocity +
             d.velocity_offset;
    }
    vcmd = std::clamp(vcmd, -lim.velocity, lim.velocity);
    const double e = vcmd - velocity_;
    const double candidate = integral_ + ki_ * e * h;
    tc = kv_ * e + candidate + d.torque;
    if (tc <= lim.torque_positive && tc >= -lim.torque_negative) integral_ = candidate;  // anti-windup
  }
  const double limited = std::clamp(tc, -lim.torque_negative, lim.torque_positive);
  if (d.kind != Kind::Off && limited != tc) torque_limited_ = true;
  torque_command_ = d.kind == Kind::Off ? 0.0 : limited;

  if (h != lag_h_) {
    lag_h_ = h;
    lag_factor_ = 1.0 - std::exp(-h / p_.current_time_constant);
  }
  torque_ += (torque_command_ - torque_) * lag_factor_;

  const double w = velocity_ * rad_per_inc_;
  const double net = torque_ - external_torque_ - p_.viscous_friction * w;
  const double j = p_.total_inertia();
  double w_new;
  if (std::abs(w) < kStandstill) {
    w_new = std::abs(net) <= p_.coulomb_friction ? 0.0 : (net - p_.coulomb_friction * sign(net)) / j * h;
  } else {
    w_new = w + (net - p_.coulomb_friction * sign(w)) / j * h;
    if (sign(w_new) != sign(w) && std::abs(net) <= p_.coulomb_friction) w_new = 0.0;  // sticks
  }
  velocity_ = w_new / rad_per_inc_;
  position_ += velocity_ * h;
}

}  // namespace ecat::ds402
