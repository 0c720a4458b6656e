#include "slave/lane_choice.hpp"

#include <pthread.h>
#include <sched.h>

#include <chrono>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "slave/chain.hpp"

namespace ecat::slave {
namespace {

using std::chrono::nanoseconds;

// A host on which everything allows two threads.
LaneHost roomy() {
  LaneHost h;
  h.cpus = 2;
  h.slaves = Chain::kMinSplitSlaves;
  h.slaves_run_apart = true;
  h.round_trip = nanoseconds(90);
  return h;
}

// One thread, for `reason`, decided before any round trip is measured.
void expect_one_before_measuring(const LaneHost& h, const std::string& reason) {
  EXPECT_FALSE(round_trip_decides(h));
  const LaneChoice c = choose_firmware_threads(h);
  EXPECT_EQ(c.threads, 1u);
  EXPECT_EQ(c.reason, reason);
}

TEST(LaneChoice, TwoThreadsWhenTheCoresAreCloseAndTheChainLongEnough) {
  const LaneChoice c = choose_firmware_threads(roomy());
  EXPECT_EQ(c.threads, 2u);
  EXPECT_EQ(c.reason, "192 slaves, 2 CPUs, a cache line between the cores and back in 90 ns");
  EXPECT_TRUE(round_trip_decides(roomy()));
}

TEST(LaneChoice, TheRoundTripLimitIsInclusive) {
  LaneHost h = roomy();
  h.round_trip = kMaxLaneRoundTrip;
  EXPECT_EQ(choose_firmware_threads(h).threads, 2u);
  h.round_trip = kMaxLaneRoundTrip + nanoseconds(1);
  const LaneChoice c = choose_firmware_threads(h);
  EXPECT_EQ(c.threads, 1u);
  EXPECT_EQ(c.reason,
            "a cache line between the cores and back takes 251 ns, more than 250 ns: two threads would be slower "
            "than one");
}

TEST(LaneChoice, OneThreadWithoutAMeasuredRoundTrip) {
  LaneHost h = roomy();
  h.round_trip.reset();
  const LaneChoice c = choose_firmware_threads(h);
  EXPECT_EQ(c.threads, 1u);
  EXPECT_EQ(c.reason, "the cores' round trip was not measured");
}

TEST(LaneChoice, OneThreadBelowTheSplitThreshold) {
  LaneHost h = roomy();
  h.slaves = Chain::kMinSplitSlaves - 1;
  expect_one_before_measuring(h, "191 slave(s): fewer than the 192 a run needs to be split");
}

TEST(LaneChoice, OneThreadOnOneCpu) {
  LaneHost h = roomy();
  h.cpus = 1;
  expect_one_before_measuring(h, "1 CPU(s): the helper would take the loop's own");
}

TEST(LaneChoice, ARealtimeLoopLeavesACpuToTheHost) {
  LaneHost h = roomy();
  h.realtime = true;
  expect_one_before_measuring(h,
                              "2 CPU(s) with --rt-priority: a spinning FIFO helper would take the CPU the rest of "
                              "the host needs (3 needed)");
  h.cpus = 3;
  EXPECT_TRUE(round_trip_decides(h));
  EXPECT_EQ(choose_firmware_threads(h).threads, 2u);
}

TEST(LaneChoice, OneThreadWhenASlaveWritesOutsideItself) {
  LaneHost h = roomy();
  h.slaves_run_apart = false;
  expect_one_before_measuring(h, "a slave's firmware writes outside itself (a trace, an SPI PDI or an external firmware)");
}

// Both threads of the probe on one CPU: the other thread runs only when the
// scheduler preempts this one, so a round trip takes a time slice. The probe
// still ends (each round stops after 20 ms) and reports a host on which two
// threads would not pay.
TEST(CacheLineRoundTrip, OnOneCpuItEndsAndReportsAFarCore) {
  Nanoseconds measured{0};
  Nanoseconds short_look{0};
  std::chrono::steady_clock::duration took{};
  std::thread probe([&] {
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(sched_getcpu(), &one);
    ASSERT_EQ(pthread_setaffinity_np(pthread_self(), sizeof one, &one), 0);
    const auto start = std::chrono::steady_clock::now();
    measured = cache_line_round_trip(2000, 3);
    took = std::chrono::steady_clock::now() - start;
    // ecat-slave's look before a trial of two threads (apps/ecat-slave/run_live.cpp):
    // one round of 256 trips, ended after 1 ms even inside a trip.
    short_look = cache_line_round_trip(256, 1, std::chrono::milliseconds(1));
  });
  probe.join();
  EXPECT_GT(measured, kMaxLaneRoundTrip);
  EXPECT_GT(short_look, kMaxLaneRoundTrip);
  // 3 rounds of at most 20 ms past their last look (16 trips of a time
  // slice each on a busy host): well under 5 s, even under a sanitizer.
  EXPECT_LT(took, std::chrono::seconds(5));
}

}  // namespace
}  // namespace ecat::slave
