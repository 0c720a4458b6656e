// The simulated axis around the motor: limit switches, home switch, encoder
// index pulse and two touch-probe marks, as intervals of motor position (in
// encoder increments). Edges are reported at their exact positions, so
// homing and touch-probe latches do not depend on the cycle time.
#pragma once

#include <cmath>
#include <optional>

#include "ds402/plant.hpp"

namespace ecat::ds402 {

enum class AxisSignal : unsigned char { NegativeLimit, PositiveLimit, HomeSwitch, Probe1, Probe2 };

class Axis {
 public:
  explicit Axis(const PlantParameters& p) noexcept : p_(p) {}

  bool active(AxisSignal s, double pos) const noexcept {
    const Interval i = interval(s);
    return pos >= i.low && pos <= i.high;
  }

  // The first boundary of signal `s` crossed going from `from` to `to`
  // (in the direction of motion), if any.
  std::optional<double> edge_between(AxisSignal s, double from, double to) const noexcept {
    const Interval i = interval(s);
    const bool was = from >= i.low && from <= i.high;
    const bool is = to >= i.low && to <= i.high;
    if (to > from) {
      if (!was && from < i.low && to >= i.low) return i.low;
      if (was && to > i.high) return i.high;
    } else if (to < from) {
      if (!was && from > i.high && to <= i.high) return i.high;
      if (was && to < i.low) return i.low;
    }
    (void)is;
    return std::nullopt;
  }

  // The first index pulse (at k·resolution + index_offset) in the half-open
  // stretch (from, to] of motion.
  std::optional<double> index_between(double from, double to) const noexcept {
    const double res = p_.encoder_resolution;
    const double off = p_.index_offset;
    if (to > from) {
      const double k = std::floor((from - off) / res) + 1.0;
      const double pos = k * res + off;
      if (pos <= to) return pos;
    } else if (to < from) {
      const double k = std::ceil((from - off) / res) - 1.0;
      const double pos = k * res + off;
      if (pos >= to) return pos;
    }
    return std::nullopt;
  }

 private:
  struct Interval {
    double low;
    double high;
  };
  Interval interval(AxisSignal s) const noexcept {
    constexpr double kInf = HUGE_VAL;
    switch (s) {
      case AxisSignal::NegativeLimit: return {-kInf, p_.negative_limit_switch};
      case AxisSignal::PositiveLimit: return {p_.positive_limit_switch, kInf};
      case AxisSignal::HomeSwitch: return {p_.home_switch_low, p_.home_switch_high};
      case AxisSignal::Probe1: return {p_.probe1_low, p_.probe1_high};
      case AxisSignal::Probe2: return {p_.probe2_low, p_.probe2_high};
    }
    return {0, -1};
  }

  PlantParameters p_;
};

}  // namespace ecat::ds402
