// Local clock model; see local_clock.hpp.
#include "esc/dc/local_clock.hpp"

#include <cmath>

namespace ecat::esc {
namespace {
constexpr double kPerPpm = 1e-6;
}

LocalClock::LocalClock(double ppm, std::uint64_t start) noexcept { reset(ppm, start); }

void LocalClock::reset(double ppm, std::uint64_t start) noexcept {
  ppm_ = ppm;
  correction_ = 0.0;
  anchor_t_ = 0;
  anchor_local_ = start;
  anchor_frac_ = 0.0;
}

double LocalClock::rate() const noexcept { return 1.0 + ppm_ * kPerPpm + correction_; }

std::uint64_t LocalClock::at(Nanoseconds t) const noexcept {
  const double elapsed = static_cast<double>(t.count() - anchor_t_) * rate() + anchor_frac_;
  const double whole = std::floor(elapsed);
  return anchor_local_ + static_cast<std::uint64_t>(static_cast<std::int64_t>(whole));
}

Nanoseconds LocalClock::when(std::uint64_t local) const noexcept {
  const auto delta = static_cast<double>(static_cast<std::int64_t>(local - anchor_local_)) - anchor_frac_;
  auto t = anchor_t_ + static_cast<std::int64_t>(std::ceil(delta / rate()));
  // Rounding of the division may leave us one ns short or long.
  while (at(Nanoseconds{t}) < local) ++t;
  while (at(Nanoseconds{t - 1}) >= local) --t;
  return Nanoseconds{t};
}

void LocalClock::set_rate_correction(Nanoseconds t, double correction) noexcept {
  const double elapsed = static_cast<double>(t.count() - anchor_t_) * rate() + anchor_frac_;
  const double whole = std::floor(elapsed);
  anchor_local_ += static_cast<std::uint64_t>(static_cast<std::int64_t>(whole));
  anchor_frac_ = elapsed - whole;
  anchor_t_ = t.count();
  correction_ = correction;
}

}  // namespace ecat::esc
