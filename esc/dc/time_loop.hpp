// The DC time control loop of one ESC (ESC datasheet Section I §9.2.3 "drift
// compensation", Section II 0x092C-0x0935; shared/spec/esc-registers.md §10).
// Each ECAT write to 0x0910 yields one comparison of the ESC's own system-time
// copy with the value the master distributed; the loop slews the local clock
// rate until they agree. The silicon's exact algorithm is not public: this is
// a second-order (PI) phase-locked loop with the same inputs and registers:
//   difference  e     = (local copy at SOF - delay) - received     (ns)
//   filtered    ē    += (e - ē) / 2^depth(0x0934)                  -> 0x092C
//   frequency   I    -= ω² · ē · dt                                -> 0x0932
//   rate correction   = I - 2ω · ē            (clamped to ±kMaxRateCorrection)
// with ω = kOmegaReset · 0x1000 / speed counter start (0x0930; larger =
// slower, as on the ESC), at most kOmegaMax so the loop stays stable at
// 1 ms between writes with filter depth 4. docs/dc.md has the measurements.
#pragma once

#include <cstdint>

#include "common/clock.hpp"
#include "esc/dc/local_clock.hpp"

namespace ecat::esc {

class TimeLoop {
 public:
  static constexpr double kOmegaReset = 20.0;  // rad/s at 0x0930 = 0x1000
  static constexpr double kOmegaMax = 50.0;
  static constexpr double kMaxRateCorrection = 1e-3;  // ±1000 ppm
  static constexpr Nanoseconds kMaxInterval{10'000'000};  // longer gaps count as 10 ms
  // 0x0932 unit: 0.1 ppm of rate correction per count.
  static constexpr double kSpeedCounterDiffUnit = 1e-7;

  // Speed counter start write (0x0930): also clears difference and
  // frequency estimate (Section II 0x0930).
  void restart(std::uint16_t speed_counter_start) noexcept;
  void set_filter_depth(std::uint8_t depth) noexcept;

  // One comparison at true time t (local time `local` at that moment).
  void compare(std::int64_t difference, Nanoseconds t, std::uint64_t local, LocalClock& clock) noexcept;

  // 0x092C: bits 30:0 |ē|, bit 31 set when the local copy is behind (< received).
  std::uint32_t difference_register() const noexcept;
  // 0x0932: frequency correction in kSpeedCounterDiffUnit, saturated.
  std::uint16_t speed_counter_diff_register() const noexcept;
  double filtered_difference() const noexcept { return filtered_; }

 private:
  static double omega_of(std::uint16_t speed_counter_start) noexcept;

  std::uint16_t speed_counter_start_ = 0x1000;
  std::uint8_t depth_ = 4;
  // Kept with the registers they come from (restart, set_filter_depth):
  // compare() runs at every ESC for every DC cycle, and these are a
  // division each.
  double omega_ = kOmegaReset;        // omega_of(speed_counter_start_)
  double filter_gain_ = 1.0 / 16.0;  // 1 / 2^depth, exact
  bool primed_ = false;
  double filtered_ = 0.0;
  double frequency_ = 0.0;
  std::uint64_t last_local_ = 0;
};

}  // namespace ecat::esc
