// The master's cycle as the slaves see it (issue 27: the page's lateness
// histogram). A cycle starts with a process-data frame whose first logical
// datagram (LRD/LWR/LRW) addresses no higher a logical address than the
// process-data frame before it: a master sends its cyclic frames in the
// same order every cycle, its image's first bytes first, so the addresses
// start over where a cycle starts (one frame per cycle: every frame is one).
// The frame path only notes the start times in a ring (no allocation, no
// division); settle(), on the loop thread at the page's or the control
// interface's rate, takes the period as the median of the recent intervals
// (again once kMedianWindow new ones have come of which at least one was
// not on time: a master keeps its cycle time, and the selection was most of
// a snapshot's cost at one drive) and
// sorts the intervals since the last settle() into lateness buckets
// relative to it. Only frames that came back are counted (Chain::count_returned):
// a cycle whose frame was lost shows as a late interval.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "common/clock.hpp"

namespace ecat::slave {

class CycleTiming {
 public:
  // Lateness of an interval against the period (interval - period, in % of
  // the period), bucket upper bounds exclusive: early below -10 %, on time
  // within +-10 %, late 10-25 %, 25-50 %, about one cycle missed (50-150 %:
  // the interval 1.5-2.5 periods), two or more (150 % and up).
  enum Bucket : std::uint8_t { Early, OnTime, Late10, Late25, Missed1, Missed2, kBuckets };
  static constexpr std::array<std::string_view, kBuckets> kBucketNames{
      "early", "on_time", "late_10_25", "late_25_50", "missed_1", "missed_2_or_more"};
  // Intervals kept between two settle() calls; more are counted unsorted.
  static constexpr std::size_t kRing = 1024;
  // Intervals the period's median is taken over.
  static constexpr std::size_t kMedianWindow = 255;

  // A returned process-data frame at `at`, its first logical address.
  void on_frame(Nanoseconds at, std::uint32_t first_logical) noexcept {
    const bool starts = !seen_ || first_logical <= last_logical_;
    seen_ = true;
    last_logical_ = first_logical;
    if (!starts) return;
    if (cycles_ != 0) {
      ring_[written_ % kRing] = (at - last_start_).count();
      ++written_;
    }
    ++cycles_;
    last_start_ = at;
  }

  // Sorts the intervals noted since the last call (loop thread only).
  void settle() noexcept;

  std::uint64_t cycles() const noexcept { return cycles_; }
  // Median of the last kMedianWindow intervals (0: none yet), taken at a
  // settle() while fewer than kMedianWindow intervals had been noted, or
  // when kMedianWindow new ones have come since it was last taken and at
  // least one of those sorted since then fell outside OnTime (a master
  // whose every interval is within +-10 % of the period keeps it).
  Nanoseconds period() const noexcept { return period_; }
  const std::array<std::uint64_t, kBuckets>& buckets() const noexcept { return buckets_; }
  // Intervals that came faster than settle() ran (more than kRing between two calls).
  std::uint64_t unsorted() const noexcept { return unsorted_; }
  // The bucket of one interval against a period (> 0).
  static Bucket bucket_of(std::int64_t interval_ns, std::int64_t period_ns) noexcept;

 private:
  std::array<std::int64_t, kRing> ring_{};
  std::uint64_t written_ = 0;  // intervals ever written
  std::uint64_t settled_ = 0;  // ... of them sorted or counted unsorted
  std::uint64_t cycles_ = 0;
  Nanoseconds last_start_{0};
  std::uint32_t last_logical_ = 0;
  bool seen_ = false;
  Nanoseconds period_{0};
  std::uint64_t median_at_ = 0;  // written_ when period_ was taken
  std::uint64_t off_time_since_median_ = 0;  // intervals sorted since then outside OnTime
  std::array<std::uint64_t, kBuckets> buckets_{};
  std::uint64_t unsorted_ = 0;
};

}  // namespace ecat::slave
