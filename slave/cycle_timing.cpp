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

namespace {
// The bucket edges of one period in nanoseconds, rounded so that comparing
// an interval with them gives exactly what comparing interval * 100 with
// period * (100 + percent) gives: no multiplication per interval (settle()
// sorts hundreds of intervals per snapshot).
constexpr std::int64_t at_least(std::int64_t percent, std::int64_t period_ns) noexcept {
  return (percent * period_ns + kPercent - 1) / kPercent;  // smallest interval with interval * 100 >= percent * period
}

struct Edges {
  std::int64_t early;    // below: Early
  std::int64_t on_time;  // up to and including: OnTime
  std::int64_t late10;   // below: Late10
  std::int64_t late25;   // below: Late25
  std::int64_t missed1;  // below: Missed1 (the interval 2 periods +- 1/2); from here Missed2
};

// For periods under 2^63 / 250 ns (over a year).
Edges edges_of(std::int64_t period_ns) noexcept {
  return {at_least(kPercent - kOnTimePercent, period_ns), (kPercent + kOnTimePercent) * period_ns / kPercent,
          at_least(kPercent + kLate25Percent, period_ns), at_least(kPercent + kLate50Percent, period_ns),
          at_least(kPercent + kMissed2Percent, period_ns)};
}

bool on_time(std::int64_t interval_ns, const Edges& e) noexcept {
  return static_cast<std::uint64_t>(interval_ns - e.early) <= static_cast<std::uint64_t>(e.on_time - e.early);
}

CycleTiming::Bucket bucket_in(std::int64_t interval_ns, const Edges& e) noexcept {
  if (interval_ns < e.early) return CycleTiming::Early;
  if (interval_ns <= e.on_time) return CycleTiming::OnTime;
  if (interval_ns < e.late10) return CycleTiming::Late10;
  if (interval_ns < e.late25) return CycleTiming::Late25;
  if (interval_ns < e.missed1) return CycleTiming::Missed1;
  return CycleTiming::Missed2;
}
}  // namespace

CycleTiming::Bucket CycleTiming::bucket_of(std::int64_t interval_ns, std::int64_t period_ns) noexcept {
  return bucket_in(interval_ns, edges_of(period_ns));
}

void CycleTiming::settle() noexcept {
  if (written_ == settled_) return;
  const std::uint64_t kept = std::min<std::uint64_t>(written_, kRing);
  const std::uint64_t oldest_kept = written_ - kept;
  if (settled_ < oldest_kept) {  // overwritten before they were sorted
    unsorted_ += oldest_kept - settled_;
    settled_ = oldest_kept;
  }
  if (period_.count() <= 0 || median_at_ < kMedianWindow ||
      (written_ - median_at_ >= kMedianWindow && off_time_since_median_ > 0)) {
    std::array<std::int64_t, kMedianWindow> window;
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(kept, kMedianWindow));
    for (std::size_t k = 0; k < n; ++k) window[k] = ring_[(written_ - 1 - k) % kRing];
    std::nth_element(window.begin(), window.begin() + static_cast<std::ptrdiff_t>(n / 2),
                     window.begin() + static_cast<std::ptrdiff_t>(n));
    period_ = Nanoseconds{window[n / 2]};
    median_at_ = written_;
    off_time_since_median_ = 0;
  }
  if (period_.count() <= 0) {  // frames at one time (simulated clock held): no period to judge by
    unsorted_ += written_ - settled_;
    settled_ = written_;
    return;
  }
  const Edges edges = edges_of(period_.count());
  // Nearly every interval of a steady master is on time: counted without a
  // branch first; the others are sorted in a second pass only when there are any.
  std::uint64_t in_time = 0;
  for (std::uint64_t k = settled_; k < written_; ++k) in_time += on_time(ring_[k % kRing], edges) ? 1U : 0U;
  if (in_time != written_ - settled_) {
    for (std::uint64_t k = settled_; k < written_; ++k) {
      const std::int64_t interval = ring_[k % kRing];
      if (on_time(interval, edges)) continue;
      ++buckets_[bucket_in(interval, edges)];
      ++off_time_since_median_;
    }
  }
  settled_ = written_;
  buckets_[OnTime] += in_time;
}

}  // namespace ecat::slave
