#include "slave/cycle_timing.hpp"

#include <algorithm>

namespace ecat::slave {

namespace {
constexpr std::int64_t kPercent = 100;
constexpr std::int64_t kOnTimePercent = 10;
constexpr std::int64_t kLate25Percent = 25;
constexpr std::int64_t kLate50Percent = 50;
constexpr std::int64_t kMissed2Percent = 150;  // the interval 2.5 periods: two cycles missed and more
}  // namespace

CycleTiming::Bucket CycleTiming::bucket_of(std::int64_t interval_ns, std::int64_t period_ns) noexcept {
  // (interval - period) * 100 / period, without overflow for any interval
  // a monotonic clock gives (under 2^63 / 100 ns: 2.9 years).
  const std::int64_t late = (interval_ns - period_ns) * kPercent;
  if (late < -kOnTimePercent * period_ns) return Early;
  if (late <= kOnTimePercent * period_ns) return OnTime;
  if (late < kLate25Percent * period_ns) return Late10;
  if (late < kLate50Percent * period_ns) return Late25;
  if (late < kMissed2Percent * period_ns) return Missed1;  // the interval 2 periods +- 1/2
  return Missed2;
}

void CycleTiming::settle() noexcept {
  if (written_ == settled_) return;
  const std::uint64_t kept = std::min<std::uint64_t>(written_, kRing);
  const std::uint64_t oldest_kept = written_ - kept;
  if (settled_ < oldest_kept) {  // overwritten before they were sorted
    unsorted_ += oldest_kept - settled_;
    settled_ = oldest_kept;
  }
  if (period_.count() <= 0 || median_at_ < kMedianWindow || written_ - median_at_ >= kMedianWindow) {
    std::array<std::int64_t, kMedianWindow> window{};
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(kept, kMedianWindow));
    for (std::size_t k = 0; k < n; ++k) window[k] = ring_[(written_ - 1 - k) % kRing];
    std::nth_element(window.begin(), window.begin() + static_cast<std::ptrdiff_t>(n / 2),
                     window.begin() + static_cast<std::ptrdiff_t>(n));
    period_ = Nanoseconds{window[n / 2]};
    median_at_ = written_;
  }
  for (; settled_ < written_; ++settled_) {
    if (period_.count() <= 0) {
      ++unsorted_;  // frames at one time (simulated clock held): no period to judge by
      continue;
    }
    ++buckets_[bucket_of(ring_[settled_ % kRing], period_.count())];
  }
}

}  // namespace ecat::slave
