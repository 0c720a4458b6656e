// slave::SpinWorkers (issue 30 item 3): every call of a batch runs once, the
// helpers' writes are visible when run() returns, a spinning and a sleeping
// helper both take part; and slave::WakeTimes' bounds kept apart and merged
// give the earliest time that the same sets in one thread give.
#include <gtest/gtest.h>
#include <pthread.h>
#include <signal.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "slave/spin_workers.hpp"
#include "slave/wake_times.hpp"

namespace ecat::slave {
namespace {

using namespace std::chrono_literals;

struct Counts {
  std::vector<std::uint32_t> runs;  // per k: how often it ran
  std::vector<unsigned> lane;       // per k: the lane that ran it
};

void count_call(void* context, std::size_t k, unsigned lane) noexcept {
  auto& c = *static_cast<Counts*>(context);
  ++c.runs[k];
  c.lane[k] = lane;
}

TEST(SpinWorkers, EveryCallOfEveryBatchRunsOnceAndItsWritesAreSeenAfterRun) {
  SpinWorkers workers(2);
  ASSERT_EQ(workers.lanes(), 3u);
  for (std::size_t count : {1u, 2u, 3u, 16u, 157u, 1000u}) {
    for (int batch = 0; batch < 200; ++batch) {
      Counts c{std::vector<std::uint32_t>(count, 0), std::vector<unsigned>(count, 99)};
      workers.run(&count_call, &c, count);
      for (std::size_t k = 0; k < count; ++k) {
        ASSERT_EQ(c.runs[k], 1u) << "count " << count << " batch " << batch << " k " << k;
        ASSERT_LT(c.lane[k], 3u);
      }
    }
  }
  workers.run(&count_call, nullptr, 0);  // an empty batch calls nothing
}

// Lane 0's call waits (real time, bounded) until a helper has run a call of
// the same batch: run() may not return before it, and helped() counts it.
struct Meeting {
  std::atomic<bool> helper_ran{false};
  std::atomic<bool> gave_up{false};
};

void meet(void* context, std::size_t /*k*/, unsigned lane) noexcept {
  auto& m = *static_cast<Meeting*>(context);
  if (lane != 0) {
    m.helper_ran.store(true);
    return;
  }
  const auto end = std::chrono::steady_clock::now() + 20s;
  while (!m.helper_ran.load()) {
    if (std::chrono::steady_clock::now() > end) {
      m.gave_up.store(true);
      return;
    }
  }
}

TEST(SpinWorkers, ASpinningHelperTakesPartAndRunWaitsForIt) {
  SpinWorkers workers(1);
  Meeting m;
  workers.run(&meet, &m, 2);
  EXPECT_TRUE(m.helper_ran.load());
  EXPECT_FALSE(m.gave_up.load());
  EXPECT_GE(workers.helped(), 1u);  // both calls when it claimed first
}

TEST(SpinWorkers, ASleepingHelperIsWokenByTheNextBatch) {
  SpinWorkers workers(1);
  // Long past kSpinsBeforeSleep pauses: the helper sleeps on its futex.
  std::this_thread::sleep_for(50ms);
  Meeting m;
  workers.run(&meet, &m, 2);
  EXPECT_TRUE(m.helper_ran.load());
  EXPECT_FALSE(m.gave_up.load());
}

// A helper blocks every signal: one sent to the process interrupts the
// loop thread's wait (ecat-slave's SIGTERM, SIGUSR1), not a spinning helper.
struct SignalMasks {
  Meeting meeting;
  std::atomic<int> helper_blocks_term{-1};
};

void look_at_mask(void* context, std::size_t k, unsigned lane) noexcept {
  auto& m = *static_cast<SignalMasks*>(context);
  if (lane != 0) {
    sigset_t mask;
    (void)pthread_sigmask(SIG_SETMASK, nullptr, &mask);
    m.helper_blocks_term.store(sigismember(&mask, SIGTERM));
  }
  meet(&m.meeting, k, lane);
}

TEST(SpinWorkers, HelpersBlockSignalsAndTheCallersMaskIsKept) {
  sigset_t before;
  ASSERT_EQ(pthread_sigmask(SIG_SETMASK, nullptr, &before), 0);
  SpinWorkers workers(1);
  sigset_t after;
  ASSERT_EQ(pthread_sigmask(SIG_SETMASK, nullptr, &after), 0);
  EXPECT_EQ(sigismember(&after, SIGTERM), sigismember(&before, SIGTERM));
  EXPECT_EQ(sigismember(&after, SIGUSR1), sigismember(&before, SIGUSR1));
  SignalMasks m;
  workers.run(&look_at_mask, &m, 2);
  ASSERT_TRUE(m.meeting.helper_ran.load());
  EXPECT_EQ(m.helper_blocks_term.load(), 1);
}

TEST(SpinWorkers, NoHelperIsOneLaneThatRunsEverything) {
  SpinWorkers workers(0);
  EXPECT_EQ(workers.lanes(), 1u);
  Counts c{std::vector<std::uint32_t>(5, 0), std::vector<unsigned>(5, 99)};
  workers.run(&count_call, &c, 5);
  EXPECT_EQ(c.runs, std::vector<std::uint32_t>(5, 1));
  EXPECT_EQ(c.lane, std::vector<unsigned>(5, 0));
  EXPECT_EQ(workers.helped(), 0u);
}

// The sets of one batch in one thread against the same sets split in two
// halves (set_apart into two bounds, merged): the same earliest() and the
// same slaves due afterwards, whichever half is merged first.
TEST(WakeTimes, BoundsKeptApartAndMergedGiveTheEarliestOfOneThread) {
  using ns = Nanoseconds;
  const std::vector<ns> start{ns{50}, ns{10}, ns{30}, ns{10}, ns{70}, ns{90}};
  struct Case {
    std::vector<std::pair<std::size_t, ns>> sets;
  };
  const std::vector<Case> cases{
      {{{1, ns{40}}, {4, ns{20}}}},               // the earliest moves later, another lower
      {{{1, ns{40}}, {3, ns{60}}}},               // both at the bound move later: a scan
      {{{1, ns{40}}}},                            // one of two at the bound moves: still 10
      {{{2, ns{5}}, {5, ns{95}}}},                // a new lowest in one half
      {{{0, ns{8}}, {5, ns{7}}}},                 // lower in both halves
      {{{0, ns{60}}, {2, ns{80}}, {4, ns{100}}}}, // nothing at the bound moves
      {{{1, ns::max()}, {3, ns::max()}, {0, ns::max()}, {2, ns::max()}, {4, ns::max()}, {5, ns::max()}}},
  };
  for (std::size_t n = 0; n < cases.size(); ++n) {
    for (bool first_half_first : {true, false}) {
      WakeTimes one;
      WakeTimes two;
      one.resize(start.size(), ns::max());
      two.resize(start.size(), ns::max());
      for (std::size_t i = 0; i < start.size(); ++i) {
        one.set(i, start[i]);
        two.set(i, start[i]);
      }
      ASSERT_EQ(one.earliest(), ns{10});
      ASSERT_EQ(two.earliest(), ns{10});
      WakeTimes::Bound low;   // slaves 0..2
      WakeTimes::Bound high;  // slaves 3..5
      for (const auto& [i, at] : cases[n].sets) {
        one.set(i, at);
        two.set_apart(i, at, i < 3 ? low : high);
      }
      two.merge(first_half_first ? low : high);
      two.merge(first_half_first ? high : low);
      EXPECT_EQ(two.earliest(), one.earliest()) << "case " << n;
      for (std::size_t i = 0; i < start.size(); ++i) EXPECT_EQ(two.time(i), one.time(i)) << "case " << n;
      std::vector<std::uint64_t> due_one(1, 0);
      std::vector<std::uint64_t> due_two(1, 0);
      one.take_due(ns{45}, due_one);
      two.take_due(ns{45}, due_two);
      EXPECT_EQ(due_two, due_one) << "case " << n;
    }
  }
}

}  // namespace
}  // namespace ecat::slave
