// Touch probe function (CiA 402-2 §8.4.13, ETG.6010 §14): 60B8h selects per
// probe enable, single/continuous trigger, the trigger source (probe input or
// encoder index pulse) and the edges; 60B9h reports enabled/stored; 60BAh-
// 60BDh hold the latched positions (position units).
#pragma once

#include <array>
#include <cstdint>

#include "ds402/axis.hpp"
#include "ds402/units.hpp"

namespace ecat::ds402 {

namespace tp {
// 60B8h, bits of probe 1 (probe 2: the same shifted by 8).
inline constexpr std::uint16_t kEnable = 1u << 0;
inline constexpr std::uint16_t kContinuous = 1u << 1;
inline constexpr std::uint16_t kTriggerMask = 0x3u << 2;
inline constexpr std::uint16_t kTriggerInput = 0x0u << 2;
inline constexpr std::uint16_t kTriggerIndex = 0x1u << 2;
inline constexpr std::uint16_t kPositiveEdge = 1u << 4;
inline constexpr std::uint16_t kNegativeEdge = 1u << 5;
// 60B9h, bits of probe 1.
inline constexpr std::uint16_t kEnabled = 1u << 0;
inline constexpr std::uint16_t kPositiveStored = 1u << 1;
inline constexpr std::uint16_t kNegativeStored = 1u << 2;
inline constexpr std::uint16_t kPositiveToggle = 1u << 6;  // continuous mode: flips on each new value
inline constexpr std::uint16_t kNegativeToggle = 1u << 7;
inline constexpr unsigned kProbe2Shift = 8;
}  // namespace tp

class TouchProbe {
 public:
  // One cycle: the motion went from `previous` to `actual` (physical
  // increments); latched values are reported at position + `shift` (homing).
  void cycle(std::uint16_t function, const Axis& axis, double previous, double actual,
             const UnitScaling& units, double shift) noexcept {
    constexpr auto kEitherEnabled = static_cast<std::uint16_t>(tp::kEnable | (tp::kEnable << tp::kProbe2Shift));
    if (!(function & kEitherEnabled)) {  // both probes off: what probe() does then, at once
      status_ = 0;
      previous_function_ = function;
      return;
    }
    cycle_enabled(function, axis, previous, actual, units, shift);
  }

  std::uint16_t status() const noexcept { return status_; }
  // 60BAh, 60BBh, 60BCh, 60BDh.
  std::int32_t value(std::size_t i) const noexcept { return values_[i]; }

 private:
  void cycle_enabled(std::uint16_t function, const Axis& axis, double previous, double actual,
                     const UnitScaling& units, double shift) noexcept;
  void probe(unsigned n, std::uint16_t function, const Axis& axis, double previous, double actual,
             const UnitScaling& units, double home_shift) noexcept;

  std::uint16_t status_ = 0;
  std::uint16_t previous_function_ = 0;
  std::array<std::int32_t, 4> values_{};
};

}  // namespace ecat::ds402
