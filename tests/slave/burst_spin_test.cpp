// slave::BurstSpin (ecat-slave --spin-us auto): while half of the last
// frames came in bursts, the spin after a frame is twice the gap three in
// four of their burst gaps stay within, at most kBurstGap; none for frames
// that come one a cycle, now and then two.
#include "slave/burst_spin.hpp"

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace ecat::slave {
namespace {

using std::chrono::microseconds;

// A master that sends `frames` frames, each `gap` after the loop finished
// the last one, the loop taking `work` per frame; returns the spin after
// the last frame. `now` ends where the loop finished it.
Nanoseconds burst(BurstSpin& s, Nanoseconds& now, std::size_t frames, Nanoseconds gap,
                  Nanoseconds work = microseconds(5)) {
  Nanoseconds spin{0};
  for (std::size_t i = 0; i < frames; ++i) {
    now += gap;
    s.frame_arrived(now);
    now += work;
    spin = s.frame_done(now);
  }
  return spin;
}

TEST(BurstSpin, TheFirstFrameGivesNoSpin) {
  BurstSpin s;
  s.frame_arrived(Nanoseconds{1'000'000});
  EXPECT_EQ(Nanoseconds{0}, s.frame_done(Nanoseconds{1'005'000}));
  EXPECT_EQ(Nanoseconds{0}, s.spin());
}

TEST(BurstSpin, FramesOfABurstGiveTwiceTheirGap) {
  BurstSpin s;
  Nanoseconds now{0};
  (void)burst(s, now, 1, microseconds(1000));  // the burst's first frame: no gap before it
  EXPECT_EQ(microseconds(60), burst(s, now, 26, microseconds(30)));
  EXPECT_EQ(microseconds(60), s.spin());
}

TEST(BurstSpin, OneFrameACycleNeverSpins) {
  BurstSpin s;
  Nanoseconds now{0};
  for (int cycle = 0; cycle < 1000; ++cycle) {
    ASSERT_EQ(Nanoseconds{0}, burst(s, now, 1, microseconds(995))) << "cycle " << cycle;
  }
}

// A master with 27 frames a cycle at 1 kHz (the project's master with 1000
// drives): the gap before a cycle's first frame is no burst gap, so the
// spin is the frames' own, and it stays after the cycle's last frame (the
// cost: one spin a cycle for nothing).
TEST(BurstSpin, ACycleOfFramesSpinsTwiceItsGapsAfterEveryFrame) {
  BurstSpin s;
  Nanoseconds now{0};
  for (int cycle = 0; cycle < 10; ++cycle) {
    (void)burst(s, now, 1, microseconds(300));  // the cycle's first frame, 300 us after the last
    ASSERT_EQ(microseconds(50), burst(s, now, 26, microseconds(25), microseconds(10))) << "cycle " << cycle;
  }
  EXPECT_EQ(microseconds(50), s.spin());
}

TEST(BurstSpin, AFrameAlreadyQueuedHasAGapOfZero) {
  BurstSpin s;
  Nanoseconds now{1'000'000};
  s.frame_arrived(now);
  now += microseconds(10);
  (void)s.frame_done(now);
  EXPECT_EQ(microseconds(60), burst(s, now, 1, microseconds(30)));
  // Four frames that arrived while the loop was still busy with the one
  // before: queued, they waited for nothing, and three in four gaps are 0.
  for (int i = 0; i < 4; ++i) {
    s.frame_arrived(now - microseconds(4));
    now += microseconds(10);
    (void)s.frame_done(now);
  }
  EXPECT_EQ(Nanoseconds{0}, s.spin());
}

TEST(BurstSpin, TheSpinIsAtMostTheBurstGap) {
  BurstSpin s;
  Nanoseconds now{0};
  EXPECT_EQ(BurstSpin::kBurstGap, burst(s, now, 3, microseconds(75)));
  // A gap of exactly kBurstGap is still a burst gap; one nanosecond more is not.
  BurstSpin edge;
  Nanoseconds t{0};
  EXPECT_EQ(BurstSpin::kBurstGap, burst(edge, t, 2, BurstSpin::kBurstGap));
  BurstSpin over;
  Nanoseconds u{0};
  EXPECT_EQ(Nanoseconds{0}, burst(over, u, 2, BurstSpin::kBurstGap + Nanoseconds{1}));
}

// Three in four burst gaps set the spin: up to a quarter of late frames do
// not raise it, one more does; kHistory frames later it is the usual again.
TEST(BurstSpin, ThreeInFourBurstGapsSetTheSpin) {
  BurstSpin s;
  Nanoseconds now{0};
  (void)burst(s, now, 1, microseconds(1000));  // no gap: the first frame
  EXPECT_EQ(microseconds(40), burst(s, now, 12, microseconds(20)));
  EXPECT_EQ(microseconds(40), burst(s, now, 4, microseconds(45)));  // 4 of 16 late
  EXPECT_EQ(microseconds(90), burst(s, now, 1, microseconds(45)));  // 5 of 17
  EXPECT_EQ(microseconds(40), burst(s, now, BurstSpin::kHistory, microseconds(20)));
}

// The project's master with 100 drives: three frames a cycle, sent
// together, so the second and third were queued when the loop finished
// the one before; now and then one comes late. The loop never spins.
TEST(BurstSpin, QueuedFramesWithALateOneNowAndThenGiveNoSpin) {
  BurstSpin s;
  Nanoseconds now{0};
  for (int cycle = 0; cycle < 100; ++cycle) {
    (void)burst(s, now, 1, microseconds(950));
    ASSERT_EQ(Nanoseconds{0}, burst(s, now, 1, cycle % 10 == 5 ? microseconds(45) : Nanoseconds{0}, microseconds(15)))
        << "cycle " << cycle;
    ASSERT_EQ(Nanoseconds{0}, burst(s, now, 1, Nanoseconds{-microseconds(10)}, microseconds(15)))
        << "cycle " << cycle;
  }
}

// A master that stops sending bursts: once fewer than half of the last
// frames came in bursts, the loop sleeps at once again.
TEST(BurstSpin, AMasterThatStopsSendingBurstsStopsTheSpin) {
  BurstSpin s;
  Nanoseconds now{0};
  EXPECT_EQ(microseconds(40), burst(s, now, 30, microseconds(20)));  // 29 burst gaps in 30 frames
  EXPECT_EQ(microseconds(40), burst(s, now, 28, microseconds(1000)));  // 29 in 58
  EXPECT_EQ(Nanoseconds{0}, burst(s, now, 1, microseconds(1000)));     // 29 in 59
}

// ecat-bench-ping's master: one frame a millisecond, and now and then,
// after a late one, the next right behind it (a gap of 50 us). Those few
// burst gaps must not make the loop spin after every frame (the first form
// of the rule did, and the spinning vCPU delayed the master's wake-up: p99
// 31-46 us -> 120-232 us).
TEST(BurstSpin, ACatchUpNowAndThenIsNoBurst) {
  BurstSpin s;
  Nanoseconds now{0};
  for (int i = 0; i < 1000; ++i) {
    ASSERT_EQ(Nanoseconds{0}, burst(s, now, 1, i % 20 == 19 ? microseconds(50) : microseconds(990))) << "frame " << i;
  }
}

// The spin kept by moves in a sorted window equals the rule computed from
// scratch (sort the burst gaps of the last kHistory frames) for every frame
// of a long random run: queued frames, burst gaps, gaps between bursts,
// equal gaps, and the 200 us edge.
TEST(BurstSpin, EveryFrameEqualsTheRuleComputedFromScratch) {
  BurstSpin s;
  std::mt19937_64 rng(20261130);
  std::deque<std::int64_t> window;  // the last kHistory gaps, -1: none
  Nanoseconds now{1'000'000};
  bool first = true;
  for (int i = 0; i < 20'000; ++i) {
    std::int64_t step = 0;
    switch (rng() % 6) {
      case 0: step = -static_cast<std::int64_t>(rng() % 20'000); break;    // queued
      case 1: step = 1'000'000; break;                                     // the next cycle
      case 2: step = BurstSpin::kBurstGap.count() + static_cast<std::int64_t>(rng() % 3) - 1; break;  // the edge
      case 3: step = 25'000; break;                                        // equal gaps
      default: step = static_cast<std::int64_t>(rng() % 120'000); break;
    }
    const Nanoseconds arrival = now + Nanoseconds{step};
    s.frame_arrived(arrival);
    const std::int64_t gap = first ? -1 : std::max<std::int64_t>(step, 0);
    window.push_back(gap <= BurstSpin::kBurstGap.count() ? gap : -1);
    if (window.size() > BurstSpin::kHistory) window.pop_front();
    first = false;
    now = std::max(now, arrival) + Nanoseconds{static_cast<std::int64_t>(rng() % 30'000)};
    std::vector<std::int64_t> burst;
    for (std::int64_t g : window) {
      if (g >= 0) burst.push_back(g);
    }
    std::sort(burst.begin(), burst.end());
    Nanoseconds want{0};
    if (!burst.empty() && 2 * burst.size() >= window.size()) {
      const std::size_t k = (burst.size() * 3 + 3) / 4 - 1;
      want = std::min(Nanoseconds{2 * burst[k]}, BurstSpin::kBurstGap);
    }
    ASSERT_EQ(want, s.frame_done(now)) << "frame " << i;
  }
}

}  // namespace
}  // namespace ecat::slave
