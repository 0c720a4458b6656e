// Local clock model; see local_clock.hpp.
#include "esc/dc/local_clock.hpp"

#include <cmath>
#include <cstdint>

namespace ecat::esc {
namespace {
constexpr double kPerPpm = 1e-6;
// Farthest a when() answer may lie from the anchor (~127 years in ns): well
// inside int64 nanoseconds, so at() stays exact around it. A local time
// beyond it (a start time written ~2^63 ns away, e.g. a corrupted 0x0990)
// is "never" in the future or "long ago" in the past.
constexpr std::int64_t kHorizon = std::int64_t{4'000'000'000'000'000'000};

std::int64_t saturating_add(std::int64_t a, std::int64_t b) noexcept {
  std::int64_t r = 0;
  if (__builtin_add_overflow(a, b, &r)) return b > 0 ? INT64_MAX : INT64_MIN;
  return r;
}
}  // namespace

LocalClock::LocalClock(double ppm, std::uint64_t start) noexcept { reset(ppm, start); }

void LocalClock::reset(double ppm, std::uint64_t start) noexcept {
  ppm_ = ppm;
  correction_ = 0.0;
  anchor_t_ = 0;
  anchor_local_ = start;
  anchor_frac_ = 0.0;
  update_rate();
}

void LocalClock::update_rate() noexcept { rate_ = 1.0 + ppm_ * kPerPpm + correction_; }

Nanoseconds LocalClock::when(std::uint64_t local) const noexcept {
  const auto delta = static_cast<double>(static_cast<std::int64_t>(local - anchor_local_)) - anchor_frac_;
  const double steps = std::ceil(delta / rate());
  if (!(std::fabs(steps) < static_cast<double>(kHorizon))) {
    return Nanoseconds{saturating_add(anchor_t_, steps > 0 ? kHorizon : -kHorizon)};
  }
  auto t = anchor_t_ + static_cast<std::int64_t>(steps);
  // Rounding of the division may leave us one ns short or long. Local time
  // is a 64-bit counter that wraps (Section I §9: system time), so "before"
  // is a signed difference, not an unsigned compare.
  const auto before = [&](std::int64_t when_t) {
    return static_cast<std::int64_t>(at(Nanoseconds{when_t}) - local) < 0;
  };
  while (before(t)) ++t;
  while (!before(t - 1)) --t;
  return Nanoseconds{t};
}

void LocalClock::anchor_at(Nanoseconds t) noexcept {
  const double elapsed = static_cast<double>(t.count() - anchor_t_) * rate() + anchor_frac_;
  const std::int64_t whole = floor_to_int64(elapsed);
  anchor_local_ += static_cast<std::uint64_t>(whole);
  anchor_frac_ = elapsed - static_cast<double>(whole);
  anchor_t_ = t.count();
}

void LocalClock::set_rate_correction(Nanoseconds t, double correction) noexcept {
  if (correction == correction_ && t.count() >= anchor_t_ && t.count() - anchor_t_ < kReanchorNs) return;
  anchor_at(t);
  correction_ = correction;
  update_rate();
}

void LocalClock::set_ppm(Nanoseconds t, double ppm) noexcept {
  anchor_at(t);
  ppm_ = ppm;
  update_rate();
}

void LocalClock::jump(Nanoseconds t, std::int64_t ns) noexcept {
  anchor_at(t);
  anchor_local_ += static_cast<std::uint64_t>(ns);  // two's complement: a negative step goes back
}

}  // namespace ecat::esc
