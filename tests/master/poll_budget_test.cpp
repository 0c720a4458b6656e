#include "master/poll_budget.hpp"

#include <gtest/gtest.h>

namespace ecat::master {
namespace {

TEST(PollBudget, StillClockEndsAfterMaxPolls) {
  ManualClock clock;
  PollBudget b(clock, std::chrono::seconds(5), 10);
  unsigned n = 0;
  while (b.next()) ++n;
  EXPECT_EQ(n, 10u);
}

TEST(PollBudget, MovingClockEndsAtTheDeadlineNotTheCount) {
  ManualClock clock;
  PollBudget b(clock, std::chrono::milliseconds(100), 10);
  unsigned n = 0;
  while (b.next()) {
    ++n;
    clock.advance(std::chrono::milliseconds(1));
  }
  EXPECT_EQ(n, 101u);  // polls at 0..100 ms
}

}  // namespace
}  // namespace ecat::master
