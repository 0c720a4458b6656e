#include "slave/burst_spin.hpp"

#include <algorithm>

namespace ecat::slave {

void BurstSpin::frame_arrived(Nanoseconds arrival) noexcept {
  Nanoseconds gap = kNoGap;
  if (have_done_) {
    // A frame that was already queued when the loop finished the last one
    // waited for nothing: a gap of 0.
    const Nanoseconds waited = std::max(arrival - last_done_, Nanoseconds{0});
    if (waited <= kBurstGap) gap = waited;
  }
  // The ring keeps the order the gaps leave in; `sorted_` the burst gaps
  // among them in order, so a frame costs two short moves, not a sort.
  const auto end = sorted_.begin() + static_cast<std::ptrdiff_t>(burst_gaps_);
  if (filled_ == kHistory && gaps_[next_] >= Nanoseconds{0}) {
    const auto leaving = std::lower_bound(sorted_.begin(), end, gaps_[next_]);
    std::copy(leaving + 1, end, leaving);
    --burst_gaps_;
  }
  if (gap >= Nanoseconds{0}) {
    const auto last = sorted_.begin() + static_cast<std::ptrdiff_t>(burst_gaps_);
    const auto at = std::upper_bound(sorted_.begin(), last, gap);
    std::copy_backward(at, last, last + 1);
    *at = gap;
    ++burst_gaps_;
  }
  gaps_[next_] = gap;
  next_ = (next_ + 1) % kHistory;
  filled_ = std::min(filled_ + 1, kHistory);
}

Nanoseconds BurstSpin::frame_done(Nanoseconds done) noexcept {
  last_done_ = done;
  have_done_ = true;
  if (burst_gaps_ == 0 || burst_gaps_ * kBurstShareIn < filled_ * kBurstShareOf) {
    spin_ = Nanoseconds{0};
    return spin_;
  }
  // The smallest gap that kQuantileOf of every kQuantileIn burst gaps stay within.
  const std::size_t k = (burst_gaps_ * kQuantileOf + kQuantileIn - 1) / kQuantileIn - 1;
  spin_ = std::min(kSpinPerGap * sorted_[k], kBurstGap);
  return spin_;
}

}  // namespace ecat::slave
