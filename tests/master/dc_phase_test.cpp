// The DC phase lock of the master's cycle (master/dc_phase.hpp) on simulated
// time: a reference clock running at its own rate against the master's clock,
// a wire latency, wake-ups that come late, a frame stamped long before it
// left. Figures asserted here are those of docs/dc.md.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <map>

#include "master/dc_phase.hpp"

namespace ecat::master {
namespace {

using std::chrono::microseconds;
using std::chrono::milliseconds;

constexpr std::int64_t kCycle = 1'000'000;

// The reference clock's system time as a function of the master's local time.
struct Reference {
  std::int64_t system_at_zero = 5'000'000'123;  // system time when local = 0
  double ppm = 80;                              // reference rate error against the master
  Nanoseconds latency = microseconds(7);        // send -> frame passes the reference
  std::uint64_t system(Nanoseconds local) const {
    const double t = static_cast<double>(local.count());
    return static_cast<std::uint64_t>(system_at_zero + std::llround(t * (1 + ppm * 1e-6)));
  }
  // First SYNC0: a whole cycle about 20 ms after local 0 (configure_sync0).
  std::uint64_t sync0_start() const {
    return (static_cast<std::uint64_t>(system_at_zero) + 20'000'000) / kCycle * kCycle + kCycle;
  }
};

struct Loop {
  Reference ref;
  DcPhaseLock lock;
  Nanoseconds now;
  std::map<std::int64_t, int> frames_per_sync0;  // SYNC0 index fed -> frames
  Loop(Reference r, DcPhaseConfig c, Nanoseconds start) : ref(r), lock(with_start(c, r)), now(start) {}
  static DcPhaseConfig with_start(DcPhaseConfig c, const Reference& r) {
    c.sync0_start = r.sync0_start();
    return c;
  }
  // One cycle: wake at the lock's time (+ `late`), send, the frame passes the
  // reference `latency` later; `stamp_early` = the clock read that long
  // before the frame really left. Returns the SYNC0 index the frame fed.
  std::int64_t cycle(Nanoseconds late = Nanoseconds{0}, Nanoseconds stamp_early = Nanoseconds{0}) {
    const Nanoseconds target = lock.next_send(now);
    now = std::max(now, target) + late;
    const std::uint64_t at_ref = ref.system(now + ref.latency + stamp_early);
    lock.update(now, at_ref);
    const auto rel = static_cast<std::int64_t>(at_ref - ref.sync0_start());
    const std::int64_t fed = (rel >= 0 ? rel / kCycle : rel / kCycle - 1) + 1;
    ++frames_per_sync0[fed];
    now += stamp_early + microseconds(120);  // the round trip
    return fed;
  }
};

TEST(DcPhaseLock, FirstFrameGoesOneCycleLaterWithoutEstimate) {
  DcPhaseLock lock(DcPhaseConfig{});
  EXPECT_EQ(lock.next_send(Nanoseconds{777}).count(), 777 + kCycle);
  EXPECT_EQ(lock.frames(), 0u);
  EXPECT_FALSE(lock.acquired());
}

// From an arbitrary start phase, with the reference 80 ppm fast and 7 us of
// wire time: the arrival settles at half a cycle before SYNC0.
TEST(DcPhaseLock, ConvergesToHalfACycleBeforeSync0) {
  Loop l(Reference{}, DcPhaseConfig{}, Nanoseconds{123'457});
  std::int64_t worst_after_150 = 0;
  for (int k = 0; k < 2000; ++k) {
    l.cycle();
    if (k >= 150) worst_after_150 = std::max(worst_after_150, std::abs(l.lock.phase_error()));
  }
  EXPECT_TRUE(l.lock.acquired());
  EXPECT_LT(worst_after_150, 1000);               // < 1 us from frame 150 on
  EXPECT_LE(std::abs(l.lock.phase_error()), 1);   // 1 ns (rounding) at the end
  EXPECT_LE(std::abs(l.lock.margin_to_sync0() - 500'000), 1);
  EXPECT_NEAR(l.lock.drift(), 80e-6, 1e-8);       // the reference's rate learnt
  EXPECT_EQ(l.lock.sync0_without_frame(), 0u);
  for (const auto& [index, n] : l.frames_per_sync0) EXPECT_EQ(n, 1) << "SYNC0 " << index;
}

TEST(DcPhaseLock, LeadIsConfigurable) {
  DcPhaseConfig c;
  c.lead = microseconds(300);
  Reference r;
  r.ppm = -100;
  Loop l(r, c, Nanoseconds{999'999});
  for (int k = 0; k < 2000; ++k) l.cycle();
  EXPECT_LE(std::abs(l.lock.phase_error()), 1);
  EXPECT_LE(std::abs(l.lock.margin_to_sync0() - 300'000), 1);
  EXPECT_NEAR(l.lock.drift(), -100e-6, 1e-8);
  EXPECT_EQ(l.lock.sync0_without_frame(), 0u);
}

// A 64-bit system time near today's (ns since 2000: ~8e17) keeps ns resolution.
TEST(DcPhaseLock, LargeSystemTimesKeepNanosecondResolution) {
  Reference r;
  r.system_at_zero = 818'000'000'000'000'000 + 4321;
  Loop l(r, DcPhaseConfig{}, Nanoseconds{42});
  for (int k = 0; k < 2000; ++k) l.cycle();
  EXPECT_LE(std::abs(l.lock.phase_error()), 1);
}

// A wake-up 7.3 ms late: the frame sent then passes SYNC0s n .. n+6 and
// feeds n+7, so 7 SYNC0 events get no frame (what the slave counts as missed
// SM events); the next frame goes to n+8 on time, not a second one to n+7,
// and the phase is as before (the stall says nothing about the clocks).
TEST(DcPhaseLock, StallCountsTheSync0sItMissedAndKeepsThePhase) {
  Loop l(Reference{}, DcPhaseConfig{}, Nanoseconds{0});
  for (int k = 0; k < 1000; ++k) l.cycle();
  ASSERT_EQ(l.lock.sync0_without_frame(), 0u);
  const std::int64_t before = l.cycle();
  const std::int64_t stalled = l.cycle(microseconds(7300));
  EXPECT_EQ(stalled, before + 8);
  EXPECT_EQ(l.lock.sync0_without_frame(), 7u);
  EXPECT_EQ(l.cycle(), stalled + 1);
  EXPECT_LE(std::abs(l.lock.phase_error()), 1);
  for (int k = 0; k < 100; ++k) l.cycle();
  EXPECT_EQ(l.lock.sync0_without_frame(), 7u);
  for (const auto& [index, n] : l.frames_per_sync0) EXPECT_EQ(n, 1) << "SYNC0 " << index;
}

// A late wake-up that still leaves the frame before its SYNC0 (400 us late
// with a 500 us lead) loses nothing.
TEST(DcPhaseLock, LateWithinTheLeadMissesNothing) {
  Loop l(Reference{}, DcPhaseConfig{}, Nanoseconds{0});
  for (int k = 0; k < 500; ++k) l.cycle();
  const std::int64_t before = l.cycle();
  EXPECT_EQ(l.cycle(microseconds(400)), before + 1);
  EXPECT_EQ(l.lock.sync0_without_frame(), 0u);
  // 400 us of local time is 400.032 us of the reference's at +80 ppm.
  EXPECT_LE(std::abs(l.lock.phase_error() - 400'032), 1);
  EXPECT_LE(std::abs(l.lock.margin_to_sync0() - 99'968), 1);
}

// A frame whose clock read was taken 3 ms before it left (preempted between
// the two): one outlier, clamped to max_step, moves the estimate by at most
// kp * max_step = 2 us; the lock is back within 10 ns in 200 frames.
TEST(DcPhaseLock, OneMisstampedFrameMovesTheLockByAtMostTheClamp) {
  Loop l(Reference{}, DcPhaseConfig{}, Nanoseconds{0});
  for (int k = 0; k < 1000; ++k) l.cycle();
  const DcPhaseLock before = l.lock;
  l.cycle(Nanoseconds{0}, milliseconds(3));
  // The error (3 ms) is clamped to max_step = 20 us: the offset moves by
  // kp * 20 us = 2 us, the drift by ki * 20 us / 1 ms = 50 ppm, which adds
  // 156 ns over the 3.12 ms from the send to l.now.
  EXPECT_LE(std::abs(l.lock.offset_at(l.now) - before.offset_at(l.now) - 2156), 1);
  EXPECT_LE(std::abs(l.lock.drift() - before.drift() - 50e-6), 1e-9);
  std::int64_t worst = 0;
  for (int k = 0; k < 200; ++k) {
    l.cycle();
    worst = std::max(worst, std::abs(l.lock.phase_error()));
  }
  EXPECT_LT(worst, 5000);
  EXPECT_LE(std::abs(l.lock.phase_error()), 10);
}

// Acquisition takes the smallest (system - local) of its first frames: one
// stamped early during acquisition does not set the offset.
TEST(DcPhaseLock, AcquisitionKeepsTheLeastDelayedFrame) {
  Reference r;
  r.ppm = 0;
  Loop l(r, DcPhaseConfig{}, Nanoseconds{0});
  l.cycle(Nanoseconds{0}, microseconds(900));  // first frame: 900 us extra
  for (int k = 0; k < 7; ++k) l.cycle();
  ASSERT_TRUE(l.lock.acquired());
  // system - local = system_at_zero + latency exactly (ppm 0).
  EXPECT_EQ(l.lock.offset_at(l.now), r.system_at_zero + 7000);
}

}  // namespace
}  // namespace ecat::master
