#include "ds402/plant.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <map>
#include <mutex>
#include <numbers>

namespace ecat::ds402 {

namespace {
constexpr double kTwoPi = 2.0 * std::numbers::pi;
// Integral zero of the velocity PI at a quarter of the loop bandwidth: about
// 50° phase margin with the current-loop lag (a common servo tuning rule).
constexpr double kIntegralZeroRatio = 0.25;
constexpr double kStandstill = 1e-9;  // rad/s below which the rotor counts as stopped
// The closed form is taken only while every clamp and friction switch stays
// clear of acting by this share of the magnitudes involved (far more than
// the rounding of either path), so the sub-steps would not have hit one.
constexpr double kMargin = 1e-9;
constexpr int kN = 4;  // closed-form state and input size

double sign(double v) noexcept { return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0); }

double dot(const double (&a)[kN], const double (&b)[kN]) noexcept {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
}

// out = a · b (out may not alias a or b).
void multiply(const double (&a)[kN][kN], const double (&b)[kN][kN], double (&out)[kN][kN]) noexcept {
  for (int i = 0; i < kN; ++i) {
    for (int j = 0; j < kN; ++j) {
      double sum = 0;
      for (int k = 0; k < kN; ++k) sum += a[i][k] * b[k][j];
      out[i][j] = sum;
    }
  }
}

}  // namespace

Plant::Plant(const PlantParameters& p) noexcept
    : p_(p), rad_per_inc_(kTwoPi / static_cast<double>(p.encoder_resolution)) {
  const double wc = kTwoPi * p_.velocity_bandwidth;
  kv_ = p_.total_inertia() * wc * rad_per_inc_;
  ki_ = kv_ * wc * kIntegralZeroRatio;
  position_ = previous_position_ = last_position_ref_ = p_.initial_position;
  has_hard_stops_ = !std::isnan(p_.negative_hard_stop) || !std::isnan(p_.positive_hard_stop);
}

// Per new cycle length: the sub-step count and length and the current-loop
// lag factor (one exp()). The closed forms' matrices are built only once
// the same length comes twice in a row (build_closed_forms): a cycle time
// that jitters (a free-running loop timed by the real clock) changes every
// cycle, and building them each time would cost far more than the
// sub-steps they save; such cycles run the sub-steps (and the rest and
// standstill paths, which need no matrices).
void Plant::configure(double dt) noexcept {
  dt_ = dt;
  n_ = std::max(1, static_cast<int>(std::ceil(dt / p_.sub_step - 1e-9)));
  h_ = dt / n_;
  inv_n_ = 1.0 / n_;
  lag_factor_ = 1.0 - std::exp(-h_ / p_.current_time_constant);
  closed_forms_.reset();
  standstill_ready_ = false;
}

void Plant::build_closed_forms() noexcept {
  try {
    closed_forms_ = shared_closed_forms();
  } catch (...) {
    // Out of memory (or a failed lock): no closed forms, the cycles run
    // the sub-steps, which give the same result (and the next cycle tries again).
    closed_forms_.reset();
  }
}

namespace {
// Everything build_linear() reads, bit for bit (NaN and -0 included): equal
// keys build equal tables.
using ClosedFormKey = std::array<std::uint64_t, 9>;
}  // namespace

// The table for this plant's inputs: the one another plant built, if one
// still uses it, else a new one. The registry holds weak references, so a
// table lives as long as a plant uses it; entries of released tables are
// dropped when the next table is added. Runs once per new cycle length (not
// per cycle), under a lock: plants may step in several threads.
std::shared_ptr<const Plant::ClosedForms> Plant::shared_closed_forms() const {
  struct Registry {
    std::mutex mutex;
    std::map<ClosedFormKey, std::weak_ptr<const ClosedForms>> tables;
  };
  static Registry registry;
  const ClosedFormKey key{static_cast<std::uint64_t>(n_),
                          std::bit_cast<std::uint64_t>(h_),
                          std::bit_cast<std::uint64_t>(lag_factor_),
                          std::bit_cast<std::uint64_t>(rad_per_inc_),
                          std::bit_cast<std::uint64_t>(kv_),
                          std::bit_cast<std::uint64_t>(ki_),
                          std::bit_cast<std::uint64_t>(p_.position_gain),
                          std::bit_cast<std::uint64_t>(p_.viscous_friction),
                          std::bit_cast<std::uint64_t>(p_.total_inertia())};
  const std::lock_guard lock(registry.mutex);
  if (const auto it = registry.tables.find(key); it != registry.tables.end()) {
    if (auto shared = it->second.lock()) return shared;
  }
  auto forms = std::make_shared<ClosedForms>();
  build_linear(forms->position_loop, LoopDemand::Kind::Position);
  build_linear(forms->velocity_loop, LoopDemand::Kind::Velocity);
  build_linear(forms->torque_loop, LoopDemand::Kind::Torque);
  std::erase_if(registry.tables, [](const auto& entry) { return entry.second.expired(); });
  registry.tables[key] = forms;
  return forms;
}

// Weights of the standstill closed form: λ(1 - λ)^(n-k) for k = n down to 1.
void Plant::build_standstill() noexcept {
  standstill_ = Standstill{1.0, {0, 0, 0}};
  const double keep = 1.0 - lag_factor_;
  for (int k = n_; k >= 1; --k) {
    const double w = lag_factor_ * standstill_.decay;  // decay = (1 - λ)^(n-k) so far
    standstill_.weight[0] += w;
    standstill_.weight[1] += w * k;
    standstill_.weight[2] += w * k * k;
    standstill_.decay *= keep;
  }
  standstill_ready_ = true;
}

// sub_step() without its clamps and friction switch, on the closed-form
// state and inputs (see Linear): the same arithmetic, in the same order.
void Plant::linear_sub_step(double s[4], const double u[4], LoopDemand::Kind mode) const noexcept {
  if (mode == LoopDemand::Kind::Torque) {  // the command is the demand u[2]; no integral, no position loop
    const double torque = s[2] + (u[2] - s[2]) * lag_factor_;
    const double w = s[1] * rad_per_inc_;
    const double w_new = w + (torque + u[3] - p_.viscous_friction * w) / p_.total_inertia() * h_;
    s[0] = 0.0;
    s[1] = w_new / rad_per_inc_;
    s[2] = torque;
    s[3] = 0.0;
    return;
  }
  const bool position = mode == LoopDemand::Kind::Position;
  const double kp = position ? p_.position_gain : 0.0;
  const double vcmd = kp * (s[0] + u[0]) + u[1];
  const double e = vcmd - s[1];
  const double integral = s[3] + ki_ * e * h_;
  const double tc = kv_ * e + integral + u[2];
  const double torque = s[2] + (tc - s[2]) * lag_factor_;
  const double w = s[1] * rad_per_inc_;
  const double w_new = w + (torque + u[3] - p_.viscous_friction * w) / p_.total_inertia() * h_;
  const double v = w_new / rad_per_inc_;
  s[0] = position ? s[0] + u[0] - v * h_ : 0.0;
  s[1] = v;
  s[2] = torque;
  s[3] = integral;
}

void Plant::build_linear(Linear& m, LoopDemand::Kind mode) const noexcept {
  const bool position = mode == LoopDemand::Kind::Position;
  m = Linear{};
  double a[kN][kN];  // column j: the sub-step's response to unit state j
  for (int j = 0; j < kN; ++j) {
    double s[kN] = {}, zero[kN] = {};
    s[j] = 1;
    linear_sub_step(s, zero, mode);
    for (int i = 0; i < kN; ++i) a[i][j] = s[i];
  }
  const double kp = position ? p_.position_gain : 0.0;
  const double g = kv_ + ki_ * h_;  // torque command per velocity error
  const double c_vcmd[kN] = {kp, 0, 0, 0};
  const double c_tc[kN] = {g * kp, -g, 0, 1};
  double power[kN][kN] = {};  // A^i
  double before_last[kN][kN] = {};  // A^(n-1)
  for (int i = 0; i < kN; ++i) power[i][i] = 1;
  for (int i = 0; i <= n_; ++i) {
    for (int k = 0; k < kN; ++k) {
      m.v_bound[k] = std::max(m.v_bound[k], std::abs(power[1][k]));
      if (i >= 1) m.travel[k] += h_ * power[1][k];
    }
    if (i == n_) break;
    if (i == n_ - 1) std::copy(&power[0][0], &power[0][0] + kN * kN, &before_last[0][0]);
    // Sub-step i + 1 commands from the state after i sub-steps.
    for (int k = 0; k < kN; ++k) {
      double vcmd = 0, tc = 0;
      for (int r = 0; r < kN; ++r) {
        vcmd += c_vcmd[r] * power[r][k];
        tc += c_tc[r] * power[r][k];
      }
      m.vcmd_bound[k] = std::max(m.vcmd_bound[k], std::abs(vcmd));
      m.tc_bound[k] = std::max(m.tc_bound[k], std::abs(tc));
      if (i == n_ - 1) m.tc_end[k] = tc;
    }
    double next[kN][kN];
    multiply(a, power, next);
    std::copy(&next[0][0], &next[0][0] + kN * kN, &power[0][0]);
  }
  std::copy(&power[0][0], &power[0][0] + kN * kN, &m.phi[0][0]);
  m.valid = h_ > 0 && std::isfinite(m.phi[0][0] + m.phi[1][1] + m.phi[2][2] + m.phi[3][3]);

  // The chord bounds: a second pass over the powers, now that the last
  // values (A^(n-1) rows for the commands, A^n for the velocity) are known.
  for (int k = 0; k < kN; ++k) {
    m.vcmd_last[k] = 0;
    for (int r = 0; r < kN; ++r) m.vcmd_last[k] += c_vcmd[r] * before_last[r][k];
  }
  for (int i = 0; i < kN; ++i) {
    for (int j = 0; j < kN; ++j) power[i][j] = i == j ? 1.0 : 0.0;
  }
  for (int i = 0; i <= n_; ++i) {
    for (int k = 0; k < kN; ++k) {
      const double first = k == 1 ? 1.0 : 0.0;  // velocity row of A^0
      const double line = first + (m.phi[1][k] - first) * i / n_;
      m.v_chord[k] = std::max(m.v_chord[k], std::abs(power[1][k] - line));
    }
    if (i == n_) break;
    const double share = n_ > 1 ? static_cast<double>(i) / (n_ - 1) : 0.0;
    for (int k = 0; k < kN; ++k) {
      double vcmd = 0, tc = 0;
      for (int r = 0; r < kN; ++r) {
        vcmd += c_vcmd[r] * power[r][k];
        tc += c_tc[r] * power[r][k];
      }
      m.vcmd_chord[k] = std::max(m.vcmd_chord[k], std::abs(vcmd - (c_vcmd[k] + (m.vcmd_last[k] - c_vcmd[k]) * share)));
      m.tc_chord[k] = std::max(m.tc_chord[k], std::abs(tc - (c_tc[k] + (m.tc_end[k] - c_tc[k]) * share)));
    }
    double next[kN][kN];
    multiply(a, power, next);
    std::copy(&next[0][0], &next[0][0] + kN * kN, &power[0][0]);
  }
}

void Plant::step(const LoopDemand& demand, const LoopLimits& limits, double dt) noexcept {
  if (dt != dt_) {
    configure(dt);
  } else if (!closed_forms_) {
    build_closed_forms();  // the same cycle length twice in a row
  }
  previous_position_ = position_;
  const bool position_mode = demand.kind == LoopDemand::Kind::Position;
  const double start_ref = (position_mode && last_was_position_) ? last_position_ref_ : demand.position;
  torque_limited_ = false;
  if (at_rest(demand, limits, start_ref)) {
    last_path_ = Path::Rest;
  } else if (velocity_ == 0.0 && standstill(demand, limits, start_ref)) {
    last_path_ = Path::Standstill;
  } else if (velocity_ != 0.0 && closed_forms_ &&
             (demand.kind == LoopDemand::Kind::Torque || demand.kind == LoopDemand::Kind::Off
                                       ? closed_form_torque(demand, limits)
                                       : closed_form(demand, limits, start_ref))) {
    last_path_ = Path::ClosedForm;
  } else {
    run_sub_steps(demand, limits, start_ref);
    last_path_ = Path::SubSteps;
  }
  apply_hard_stops();
  last_was_position_ = position_mode;
  last_position_ref_ = demand.position;
}

// An end stop ends the cycle's travel: the rotor is put back on it and
// stops dead (an inelastic stop, resolved once per cycle). NaN: no stop.
void Plant::apply_hard_stops() noexcept {
  at_hard_stop_ = false;
  if (held_) [[unlikely]] {  // the brake: the rotor did not move in this step
    position_ = previous_position_;
    velocity_ = 0;
    return;
  }
  if (!has_hard_stops_) return;
  if (position_ >= p_.positive_hard_stop) {
    position_ = p_.positive_hard_stop;
    if (velocity_ > 0) velocity_ = 0;
    at_hard_stop_ = true;
  } else if (position_ <= p_.negative_hard_stop) {
    position_ = p_.negative_hard_stop;
    if (velocity_ < 0) velocity_ = 0;
    at_hard_stop_ = true;
  }
}

void Plant::step_by_sub_steps(const LoopDemand& demand, const LoopLimits& limits, double dt) noexcept {
  if (dt != dt_) configure(dt);
  previous_position_ = position_;
  const bool position_mode = demand.kind == LoopDemand::Kind::Position;
  const double start_ref = (position_mode && last_was_position_) ? last_position_ref_ : demand.position;
  torque_limited_ = false;
  run_sub_steps(demand, limits, start_ref);
  last_path_ = Path::SubSteps;
  apply_hard_stops();
  last_was_position_ = position_mode;
  last_position_ref_ = demand.position;
}

void Plant::run_sub_steps(const LoopDemand& d, const LoopLimits& lim, double start_ref) noexcept {
  for (int i = 1; i <= n_; ++i) {
    const double ref = start_ref + (d.position - start_ref) * static_cast<double>(i) / n_;
    sub_step(d, lim, ref, h_);
  }
}

// The rest point: the rotor stands (and friction holds it), the reference
// stays where the rotor is, nothing commands a velocity and the torque has
// settled on the command. Then every sub-step leaves the state exactly as it
// is (sub_step() computes e = 0, the same command, no torque change and
// w = 0), so the cycle is done without running them.
bool Plant::at_rest(const LoopDemand& d, const LoopLimits& lim, double start_ref) noexcept {
  using Kind = LoopDemand::Kind;
  if (velocity_ != 0.0 || !(std::abs(torque_ - external_torque_) <= p_.coulomb_friction)) return false;
  double tc = 0;
  switch (d.kind) {
    case Kind::Off: break;
    case Kind::Torque: {
      const double upper = kv_ * lim.velocity;
      const double lower = kv_ * -lim.velocity;
      tc = std::clamp(d.torque, std::min(lower, upper), std::max(lower, upper));
      break;
    }
    case Kind::Position:
      if (start_ref != position_ || d.position != position_ ||
          p_.velocity_feed_forward * d.velocity + d.velocity_offset != 0.0)
        return false;
      tc = integral_ + d.torque;
      break;
    case Kind::Velocity:
      if (d.velocity + d.velocity_offset != 0.0) return false;
      tc = integral_ + d.torque;
      break;
  }
  if (torque_ != tc || !(tc <= lim.torque_positive && tc >= -lim.torque_negative)) return false;
  if (d.kind == Kind::Off || d.kind == Kind::Torque) integral_ = 0;
  torque_command_ = tc;
  velocity_ = 0.0;
  return true;
}

// All n sub-steps at once while they are linear (see Linear): the velocity
// and torque commands stay inside their limits and the rotor turns the same
// way throughout, by bounds on the transient s_0 - ss that hold for every
// sub-step. Otherwise false, and the sub-steps run one by one.
bool Plant::closed_form(const LoopDemand& d, const LoopLimits& lim, double start_ref) noexcept {
  const bool position = d.kind == LoopDemand::Kind::Position;
  const Linear& m = position ? closed_forms_->position_loop : closed_forms_->velocity_loop;
  if (!m.valid || !(std::abs(velocity_ * rad_per_inc_) >= kStandstill)) return false;
  const double turning = velocity_ > 0 ? 1.0 : -1.0;
  const double u[kN] = {position ? (d.position - start_ref) * inv_n_ : 0.0,
                        position ? p_.velocity_feed_forward * d.velocity + d.velocity_offset
                                 : d.velocity + d.velocity_offset,
                        d.torque, -external_torque_ - p_.coulomb_friction * turning};
  const double s0[kN] = {position ? start_ref - position_ : 0.0, velocity_, torque_, integral_};
  // The steady state: the velocity of the reference ramp (or the velocity
  // command), no velocity error, the torque that balances friction and load
  // at that velocity, the integral that gives it.
  const double kp = position ? p_.position_gain : 0.0;
  const double v_ss = position ? u[0] / h_ : u[1];
  const double t_ss = p_.viscous_friction * rad_per_inc_ * v_ss - u[3];
  const double ss[kN] = {position ? (v_ss - u[1]) / kp - u[0] : 0.0, v_ss, t_ss, t_ss - u[2]};
  double delta[kN], size[kN];
  for (int i = 0; i < kN; ++i) {
    delta[i] = s0[i] - ss[i];
    size[i] = std::abs(delta[i]);
  }
  // Whether a quantity stays inside [low, high] in every sub-step: its
  // steady value ± the swing bound, or else (tighter for slow transients)
  // between its first and last values ± the chord bound, or both.
  auto inside = [&](double steady, const double (&swing)[kN], const double (&first)[kN], const double (&last)[kN],
                    const double (&chord)[kN], double low, double high, double scale) {
    const double r = dot(swing, size);
    const double margin = kMargin * (scale + std::abs(steady) + r);
    double lo = steady - r - margin, hi = steady + r + margin;
    if (lo >= low && hi <= high) return true;
    const double a = steady + dot(first, delta), b = steady + dot(last, delta), c = dot(chord, size);
    const double chord_margin = kMargin * (scale + std::abs(steady) + std::abs(a) + std::abs(b) + c);
    lo = std::max(lo, std::min(a, b) - c - chord_margin);
    hi = std::min(hi, std::max(a, b) + c + chord_margin);
    return lo >= low && hi <= high;
  };
  // Velocity command: never clamped.
  const double vcmd = kp * (ss[0] + u[0]) + u[1];
  const double c_vcmd[kN] = {kp, 0, 0, 0};
  if (!inside(vcmd, m.vcmd_bound, c_vcmd, m.vcmd_last, m.vcmd_chord, -lim.velocity, lim.velocity,
              kp * (std::abs(ss[0]) + std::abs(u[0])) + std::abs(u[1])))
    return false;
  // Torque command: never at a limit (so the integral is never held either).
  const double g = kv_ + ki_ * h_;
  const double tc = g * (vcmd - ss[1]) + ss[3] + u[2];
  const double c_tc[kN] = {g * kp, -g, 0, 1};
  if (!inside(tc, m.tc_bound, c_tc, m.tc_end, m.tc_chord, -lim.torque_negative, lim.torque_positive,
              g * (std::abs(vcmd) + std::abs(ss[1])) + std::abs(ss[3]) + std::abs(u[2])))
    return false;
  // Velocity: the same sign, clear of standstill, before and after every sub-step.
  const double c_v[kN] = {0, 1, 0, 0};
  const double clear = 2 * kStandstill / rad_per_inc_;
  if (!(turning > 0 ? inside(ss[1], m.v_bound, c_v, m.phi[1], m.v_chord, clear, HUGE_VAL, 0.0)
                    : inside(ss[1], m.v_bound, c_v, m.phi[1], m.v_chord, -HUGE_VAL, -clear, 0.0)))
    return false;

  position_ += ss[1] * dt_ + dot(m.travel, delta);
  velocity_ = ss[1] + dot(m.phi[1], delta);
  torque_ = ss[2] + dot(m.phi[2], delta);
  integral_ = ss[3] + dot(m.phi[3], delta);
  torque_command_ = tc + dot(m.tc_end, delta);
  return true;
}

// The rotor stands (velocity exactly 0) and friction holds it in every
// sub-step: the position and velocity stay, and only the controller moves.
// Its velocity error is then the velocity command, linear in the sub-step
// k (the reference ramps), so the integral and the torque command tc_k are
// quadratic in k, and the lagged torque T_k, a running weighted mean of
// T_0 and the tc_k, stays between their extremes. The sub-steps would hold
// the rotor if that range is inside the friction band |T - load| <= Fc; the
// commands must stay inside their clamps as in closed_form().
bool Plant::standstill(const LoopDemand& d, const LoopLimits& lim, double start_ref) noexcept {
  using Kind = LoopDemand::Kind;
  if (velocity_ != 0.0) return false;
  if (!standstill_ready_) build_standstill();
  const double n = n_;
  double c0 = 0, c1 = 0, c2 = 0;  // torque command of sub-step k: c0 + c1 k + c2 k², k = 1..n
  double integral_end = 0;
  bool limited = false;
  switch (d.kind) {
    case Kind::Off: break;
    case Kind::Torque: {
      const double upper = kv_ * lim.velocity;
      const double lower = kv_ * -lim.velocity;
      const double tc = std::clamp(d.torque, std::min(lower, upper), std::max(lower, upper));
      c0 = std::clamp(tc, -lim.torque_negative, lim.torque_positive);
      limited = c0 != tc;
      break;
    }
    case Kind::Position:
    case Kind::Velocity: {
      const bool position = d.kind == Kind::Position;
      const double kp = p_.position_gain;
      // Velocity command (= error) of sub-step k: a + b k.
      const double a = position ? kp * (start_ref - position_) + p_.velocity_feed_forward * d.velocity + d.velocity_offset
                                : d.velocity + d.velocity_offset;
      const double b = position ? kp * (d.position - start_ref) * inv_n_ : 0.0;
      const double first = a + b, last = a + b * n;
      if (!(std::max(std::abs(first), std::abs(last)) + kMargin * (std::abs(a) + std::abs(b) * n) <= lim.velocity))
        return false;
      const double kih = ki_ * h_;
      c2 = kih * b / 2;
      c1 = kv_ * b + kih * (a + b / 2);
      c0 = kv_ * a + integral_ + d.torque;
      integral_end = integral_ + kih * (a * n + b * n * (n + 1) / 2);
      break;
    }
  }
  // Extremes of tc_k over k in [1, n] (the whole interval: a superset).
  const double tc_first = c0 + c1 + c2, tc_last = c0 + c1 * n + c2 * n * n;
  double lo = std::min(tc_first, tc_last), hi = std::max(tc_first, tc_last);
  if (c2 != 0) {
    const double vertex = -c1 / (2 * c2);
    if (vertex > 1 && vertex < n) {
      const double at = c0 + c1 * vertex + c2 * vertex * vertex;
      lo = std::min(lo, at);
      hi = std::max(hi, at);
    }
  }
  const double margin = kMargin * (std::abs(c0) + std::abs(c1) * n + std::abs(c2) * n * n + std::abs(torque_) +
                                   std::abs(external_torque_) + p_.coulomb_friction);
  if ((d.kind == Kind::Position || d.kind == Kind::Velocity) &&
      !(lo - margin >= -lim.torque_negative && hi + margin <= lim.torque_positive))
    return false;
  // Friction holds: net torque (velocity 0, so no viscous part) in the band.
  const double t_lo = std::min(lo, torque_) - margin, t_hi = std::max(hi, torque_) + margin;
  if (!(t_hi - external_torque_ <= p_.coulomb_friction && t_lo - external_torque_ >= -p_.coulomb_friction))
    return false;

  const Standstill& s = standstill_;
  torque_ = s.decay * torque_ + s.weight[0] * c0 + s.weight[1] * c1 + s.weight[2] * c2;
  torque_command_ = d.kind == Kind::Off ? 0.0 : tc_last;
  integral_ = integral_end;
  torque_limited_ = limited;
  velocity_ = 0.0;
  return true;
}

// The torque modes while turning: the same closed form (see closed_form())
// with the command fixed at the demand. It holds while the demand is inside
// the torque limits and the speed limitation does not act, i.e. the
// velocity stays within ±limit − demand/Kv, and the rotor turns one way.
// Switched off (coasting) is the same with a command of 0 and no limits.
bool Plant::closed_form_torque(const LoopDemand& d, const LoopLimits& lim) noexcept {
  const Linear& m = closed_forms_->torque_loop;
  const double b = p_.viscous_friction * rad_per_inc_;
  if (!m.valid || !(b > 0) || !(std::abs(velocity_ * rad_per_inc_) >= kStandstill)) return false;
  const bool off = d.kind == LoopDemand::Kind::Off;
  const double command = off ? 0.0 : d.torque;
  if (!off && !(command <= lim.torque_positive && command >= -lim.torque_negative)) return false;
  const double turning = velocity_ > 0 ? 1.0 : -1.0;
  // Steady state: the torque at the demand, the speed where viscous friction
  // takes what Coulomb friction and load leave of it.
  const double t_ss = command;
  const double v_ss = (t_ss - external_torque_ - p_.coulomb_friction * turning) / b;
  // Far beyond the motion at hand the sums would cancel too much: sub-steps.
  if (!(std::abs(v_ss) <= 1e3 * (std::abs(velocity_) + lim.velocity))) return false;
  const double delta[kN] = {0.0, velocity_ - v_ss, torque_ - t_ss, 0.0};
  const double size[kN] = {0.0, std::abs(delta[1]), std::abs(delta[2]), 0.0};
  const double shift = command / kv_;
  const double clear = 2 * kStandstill / rad_per_inc_;
  const double reach = off ? HUGE_VAL : lim.velocity;  // no speed limitation when off
  const double low = turning > 0 ? std::max(clear, -reach - shift) : -reach - shift;
  const double high = turning > 0 ? reach - shift : std::min(-clear, reach - shift);
  const double r = dot(m.v_bound, size);
  const double margin = kMargin * (lim.velocity + std::abs(shift) + std::abs(v_ss) + r);
  double lo = v_ss - r - margin, hi = v_ss + r + margin;
  if (!(lo >= low && hi <= high)) {
    const double first = velocity_, last = v_ss + dot(m.phi[1], delta), c = dot(m.v_chord, size);
    const double chord_margin =
        kMargin * (lim.velocity + std::abs(shift) + std::abs(v_ss) + std::abs(first) + std::abs(last) + c);
    lo = std::max(lo, std::min(first, last) - c - chord_margin);
    hi = std::min(hi, std::max(first, last) + c + chord_margin);
    if (!(lo >= low && hi <= high)) return false;
  }
  position_ += v_ss * dt_ + dot(m.travel, delta);
  velocity_ = v_ss + dot(m.phi[1], delta);
  torque_ = t_ss + dot(m.phi[2], delta);
  integral_ = 0;
  torque_command_ = command;
  return true;
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
