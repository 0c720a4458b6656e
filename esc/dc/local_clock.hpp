// The free-running local clock of one ESC (ESC datasheet Section I §9.1:
// "local time", 1 ns units, 64 bit). A simulated slave's oscillator has its
// own frequency error (ppm) and start value, so a chain of simulated slaves
// really drifts apart; the DC time loop slews it through rate_correction().
// Time in: the injected (true) time; time out: this ESC's local time.
#pragma once

#include <cmath>
#include <cstdint>

#include "common/clock.hpp"

namespace ecat::esc {

// floor(x) as an integer, for x inside the int64 range (as the cast of
// std::floor's result needs too): truncation, one down for a negative
// fraction. Without SSE4.1 std::floor is a library call, and every DC
// comparison at every ESC takes two.
inline std::int64_t floor_to_int64(double x) noexcept {
  const auto i = static_cast<std::int64_t>(x);
  return static_cast<double>(i) > x ? i - 1 : i;
}

class LocalClock {
 public:
  // `ppm`: oscillator error, e.g. +100 runs 100 µs/s fast. `start`: local time
  // at true time 0 (an ESC's clock starts at power-on, not at system time).
  explicit LocalClock(double ppm = 0.0, std::uint64_t start = 0) noexcept;

  // Local time at true time t (rounded down to whole ns). Piecewise linear,
  // strictly increasing in t.
  std::uint64_t at(Nanoseconds t) const noexcept {
    const double elapsed = static_cast<double>(t.count() - anchor_t_) * rate_ + anchor_frac_;
    return anchor_local_ + static_cast<std::uint64_t>(floor_to_int64(elapsed));
  }
  // Earliest true time at which the local time reaches `local` (rounded up).
  Nanoseconds when(std::uint64_t local) const noexcept;

  // Sets the correction applied from true time t on (dimensionless, e.g.
  // -1e-4 slows the clock by 100 ppm). The clock stays continuous at t.
  // The correction it has, within kReanchorNs of the anchor, changes
  // nothing (the same line: a settled time loop sets it so at every ESC
  // every DC cycle, issue 30).
  void set_rate_correction(Nanoseconds t, double correction) noexcept;
  // How far from its anchor the clock moves it again for an unchanged
  // correction: (t - anchor) x rate stays exact to far below 1 ns.
  static constexpr std::int64_t kReanchorNs = std::int64_t{1} << 32;
  double rate_correction() const noexcept { return correction_; }
  double ppm() const noexcept { return ppm_; }
  // Effective rate (local ns per true ns).
  double rate() const noexcept { return rate_; }

  // Re-initialises as at power-on.
  void reset(double ppm, std::uint64_t start) noexcept;

  // Faults (slave::FaultCatalogue dc_drift, dc_time_jump; docs/faults.md):
  // the oscillator's error becomes `ppm` from true time t on (the clock stays
  // continuous at t), or the local time steps by `ns` at t (negative: back).
  void set_ppm(Nanoseconds t, double ppm) noexcept;
  void jump(Nanoseconds t, std::int64_t ns) noexcept;

 private:
  double ppm_ = 0.0;
  double correction_ = 0.0;
  // Anchor: local time (integer + fraction) at true time anchor_t_.
  std::int64_t anchor_t_ = 0;
  std::uint64_t anchor_local_ = 0;
  double anchor_frac_ = 0.0;
  // 1 + ppm * 1e-6 + correction, kept with them (same value as computed
  // on each use: at() runs for every DC register access).
  double rate_ = 1.0;
  void update_rate() noexcept;
  void anchor_at(Nanoseconds t) noexcept;  // moves the anchor to t, the clock unchanged
};

}  // namespace ecat::esc
