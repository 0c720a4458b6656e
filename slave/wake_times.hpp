// The slaves of a chain by the time they next need to run (issue 16 item 5,
// issue 30): one time per slave in a flat array and a lower bound on all of
// them (exact, by a scan, when asked: earliest()). Setting a time is a store
// and a compare; the ones due are found by a scan of the array, made only
// when the time reaches the lower bound (as esc::SkipIndex::mark_due does
// for the ESCs' timers). It replaced an
// indexed min-heap whose sift on every set cost the 100-drive CSP cycle
// more than the scans it saved (docs/performance-log.md "Session 11").
// Sized at set-up; nothing allocates afterwards.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "common/clock.hpp"

namespace ecat::slave {

class WakeTimes {
 public:
  static constexpr std::size_t kWordBits = 64;

  // Set-up: slaves 0..n-1, the new ones waking at `at`.
  void resize(std::size_t n, Nanoseconds at = Nanoseconds::min()) {
    if (n > at_.size() && at <= earliest_) {
      earliest_ = at;
      exact_ = true;
    }
    if (n < at_.size()) exact_ = false;
    at_.resize(n, at);
  }
  Nanoseconds time(std::size_t i) const noexcept { return at_[i]; }
  void set(std::size_t i, Nanoseconds at) noexcept {
    if (at <= earliest_) {
      earliest_ = at;
      exact_ = true;
    } else if (at_[i] == earliest_) {
      exact_ = false;  // the earliest one moved later: earliest() scans
    }
    at_[i] = at;
  }
  // set() from several threads at once, each for slaves of its own
  // (slave::Chain's firmware lanes): the times are stored, and what each
  // thread's sets do to the lower bound is kept in its Bound, merged by one
  // thread afterwards. The result does not depend on how the slaves were
  // split: the bound is exact when the lowest time set is at or below it,
  // and stays exact unless a slave at the bound moved later.
  struct Bound {
    Nanoseconds lowest = Nanoseconds::max();  // of the times set
    bool moved = false;                       // a slave at the bound moved later
  };
  void set_apart(std::size_t i, Nanoseconds at, Bound& b) noexcept {
    b.lowest = std::min(b.lowest, at);
    b.moved = b.moved || (at_[i] == earliest_ && at > earliest_);
    at_[i] = at;
  }
  void merge(const Bound& b) noexcept {
    if (b.lowest <= earliest_) {
      earliest_ = b.lowest;
      exact_ = true;
    } else if (b.moved) {
      exact_ = false;
    }
  }

  // The earliest time of all, exactly (Nanoseconds::max(): none, or no
  // slave): a scan only when a set() moved the earliest one later.
  Nanoseconds earliest() noexcept {
    if (!exact_) {
      earliest_ = at_.empty() ? Nanoseconds::max() : *std::min_element(at_.begin(), at_.end());
      exact_ = true;
    }
    return earliest_;
  }

  // Every slave whose time is <= now: bit i of word i / 64 set in `due`,
  // its time set to Nanoseconds::max() (the caller sets it again).
  void take_due(Nanoseconds now, std::span<std::uint64_t> due) noexcept {
    if (earliest_ > now) return;
    Nanoseconds earliest = Nanoseconds::max();
    for (std::size_t i = 0; i < at_.size(); ++i) {
      if (at_[i] <= now) {
        due[i / kWordBits] |= std::uint64_t{1} << (i % kWordBits);
        at_[i] = Nanoseconds::max();
      } else {
        earliest = std::min(earliest, at_[i]);
      }
    }
    earliest_ = earliest;
    exact_ = true;
  }

 private:
  std::vector<Nanoseconds> at_;  // per slave: when it wakes
  // No slave wakes before this (a lower bound: set() only lowers it, a scan sets it exactly).
  Nanoseconds earliest_ = Nanoseconds::max();
  bool exact_ = true;  // earliest_ is the earliest time, not only a bound
};

}  // namespace ecat::slave
