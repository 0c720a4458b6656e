// Ends a register-polling loop: at its deadline on a clock that moves (wire,
// or a simulated clock advanced per frame), or after `max_polls` polls when
// the clock does not move at all, so no loop can hang (nothing here sleeps).
#pragma once

#include "common/clock.hpp"

namespace ecat::master {

class PollBudget {
 public:
  PollBudget(const Clock& clock, Nanoseconds timeout, unsigned max_polls) noexcept
      : clock_(clock), start_(clock.now()), deadline_(start_ + timeout), max_polls_(max_polls) {}

  // Call before each poll; false = give up.
  bool next() noexcept {
    if (polls_++ == 0) return true;
    const Nanoseconds now = clock_.now();
    if (now > deadline_) return false;
    return now != start_ || polls_ <= max_polls_;
  }

 private:
  const Clock& clock_;
  Nanoseconds start_;
  Nanoseconds deadline_;
  unsigned max_polls_;
  unsigned polls_ = 0;
};

}  // namespace ecat::master
