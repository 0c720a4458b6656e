#include "ds402/touch_probe.hpp"

namespace ecat::ds402 {

void TouchProbe::cycle_enabled(std::uint16_t function, const Axis& axis, double previous, double actual,
                               const UnitScaling& units, double shift) noexcept {
  probe(0, function, axis, previous, actual, units, shift);
  probe(1, function, axis, previous, actual, units, shift);
  previous_function_ = function;
}

void TouchProbe::probe(unsigned n, std::uint16_t function, const Axis& axis, double previous, double actual,
                       const UnitScaling& units, double home_shift) noexcept {
  const unsigned shift = n * tp::kProbe2Shift;
  const auto f = static_cast<std::uint16_t>(function >> shift);
  const auto before = static_cast<std::uint16_t>(previous_function_ >> shift);
  auto st = static_cast<std::uint16_t>(status_ >> shift);
  auto rising = [&](std::uint16_t bit) { return (f & bit) && !(before & bit); };

  if (!(f & tp::kEnable)) {
    st = 0;
  } else {
    if (rising(tp::kEnable)) st = tp::kEnabled;
    // An edge whose sampling is off shows nothing stored; switching it on
    // (again) re-arms it for a single trigger.
    if (!(f & tp::kPositiveEdge) || rising(tp::kPositiveEdge))
      st = static_cast<std::uint16_t>(st & ~(tp::kPositiveStored | tp::kPositiveToggle));
    if (!(f & tp::kNegativeEdge) || rising(tp::kNegativeEdge))
      st = static_cast<std::uint16_t>(st & ~(tp::kNegativeStored | tp::kNegativeToggle));

    double pos_edge = 0, neg_edge = 0;
    bool has_pos = false, has_neg = false;
    if ((f & tp::kTriggerMask) == tp::kTriggerIndex) {
      if (const auto i = axis.index_between(previous, actual)) {
        pos_edge = neg_edge = *i;  // the index is a short pulse: both edges at once
        has_pos = has_neg = true;
      }
    } else {
      const AxisSignal s = n == 0 ? AxisSignal::Probe1 : AxisSignal::Probe2;
      if (const auto e = axis.edge_between(s, previous, actual)) {
        if (axis.active(s, actual)) {
          pos_edge = *e;
          has_pos = true;
        } else {
          neg_edge = *e;
          has_neg = true;
        }
      }
    }
    const bool continuous = f & tp::kContinuous;
    auto latch = [&](bool has, std::uint16_t enable, std::uint16_t stored, std::uint16_t toggle, double pos,
                     std::size_t slot) {
      if (!has || !(f & enable)) return;
      if (!continuous && (st & stored)) return;
      values_[n * 2 + slot] = UnitScaling::to_i32(units.to_user(pos + home_shift));
      st = static_cast<std::uint16_t>(st | stored);
      if (continuous) st = static_cast<std::uint16_t>(st ^ toggle);
    };
    latch(has_pos, tp::kPositiveEdge, tp::kPositiveStored, tp::kPositiveToggle, pos_edge, 0);
    latch(has_neg, tp::kNegativeEdge, tp::kNegativeStored, tp::kNegativeToggle, neg_edge, 1);
  }
  const auto mask = static_cast<std::uint16_t>(0x00FFu << shift);
  status_ = static_cast<std::uint16_t>((status_ & ~mask) | ((st << shift) & mask));
}

}  // namespace ecat::ds402
