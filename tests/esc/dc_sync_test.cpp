// SYNC0/SYNC1 generation and LATCH inputs (ESC datasheet Section I §9.2.4-5,
// Section II 0x0980-0x09CF): pulses at start + k * cycle within one 10 ns
// tick of this ESC's system time, single shot, SYNC1 shift and multiple,
// acknowledge mode, start time checks, ownership, latches.
#include <gtest/gtest.h>

#include <vector>

#include "dc_fixture.hpp"

namespace ecat::esc::test {
namespace {

using namespace dcreg;

struct Edge {
  unsigned signal;
  bool level;
  Nanoseconds t;
};

struct Recorder : DcObserver {
  std::vector<Edge> edges;
  void on_sync(unsigned signal, bool level, Nanoseconds t) noexcept override { edges.push_back({signal, level, t}); }
  std::vector<Nanoseconds> rising(unsigned signal) const {
    std::vector<Nanoseconds> out;
    for (const Edge& e : edges) {
      if (e.signal == signal && e.level) out.push_back(e.t);
    }
    return out;
  }
};

constexpr std::uint64_t kOffset = 0x0800'0000'0000'0000ull;
constexpr std::uint64_t kTick = 10;  // ns, one ESC clock tick

class DcSyncTest : public ::testing::Test {
 protected:
  void SetUp() override { init(100); }
  void init(std::uint16_t pulse_length) {
    dc.set_clock(37.0, 123'456);
    dc.reset(pulse_length);
    dc.set_observer(&rec);
    dc_write(dc, kSystemTimeOffset, kOffset, 8, Nanoseconds{0});
  }
  std::uint64_t now_system() { return dc.system_time(now); }
  void program(std::uint64_t start, std::uint32_t cycle0, std::uint32_t cycle1, std::uint8_t activation) {
    dc_write(dc, kActivation, 0, 1, now);
    dc_write(dc, kStartTimeCyclicOperation, start, 8, now);
    dc_write(dc, kSync0CycleTime, cycle0, 4, now);
    dc_write(dc, kSync1CycleTime, cycle1, 4, now);
    dc_write(dc, kActivation, activation, 1, now);
  }
  // Runs poll() at every deadline it returns until `until`.
  void run_until(Nanoseconds until) {
    for (int guard = 0; guard < 100000; ++guard) {
      const std::optional<Nanoseconds> next = dc.poll(now);
      if (!next || *next > until) break;
      now = std::max(*next, now);
    }
    now = until;
    dc.poll(now);
  }
  void expect_at(const std::vector<Nanoseconds>& pulses, std::uint64_t first, std::uint64_t step) {
    for (std::size_t k = 0; k < pulses.size(); ++k) {
      const std::uint64_t target = first + k * step;
      const std::uint64_t seen = dc.system_time(pulses[k]);
      EXPECT_GE(seen, target) << k;
      EXPECT_LT(seen, target + kTick) << k;
      // The edge's true time is the earliest at which the system time reaches it.
      EXPECT_LT(dc.system_time(pulses[k] - Nanoseconds{1}), target) << k;
    }
  }

  DcUnit dc;
  Recorder rec;
  Nanoseconds now{ms(1)};
};

TEST_F(DcSyncTest, Sync0PulsesAtStartPlusKCycles) {
  const std::uint64_t start = now_system() + 10'000'000;
  program(start, 1'000'000, 0, kActivateSyncUnit | kActivateSync0);
  EXPECT_EQ(dc_read(dc, kActivationStatus, 1, now), kFirstSync0Pending);
  run_until(now + ms(30) - us(100));
  const auto pulses = rec.rising(0);
  ASSERT_EQ(pulses.size(), 20u);  // from +10 ms every ms up to +29 ms
  expect_at(pulses, start, 1'000'000);
  EXPECT_EQ(dc_read(dc, kActivationStatus, 1, now), 0u);
  EXPECT_TRUE(rec.rising(1).empty());
  // Pulse mode: each pulse ends 0x0982 x 10 ns = 1 µs later.
  ASSERT_GE(rec.edges.size(), 2u);
  EXPECT_FALSE(rec.edges[1].level);
  EXPECT_NEAR(static_cast<double>((rec.edges[1].t - rec.edges[0].t).count()), 1000.0, 1.0);
}

TEST_F(DcSyncTest, NextSync0IsReadableAt0x0990) {
  const std::uint64_t start = now_system() + 5'000'000;
  program(start, 2'000'000, 0, kActivateSyncUnit | kActivateSync0);
  EXPECT_EQ(dc_read(dc, kStartTimeCyclicOperation, 8, now), start);
  run_until(now + ms(6));
  EXPECT_EQ(dc_read(dc, kStartTimeCyclicOperation, 8, now), start + 2'000'000);
}

TEST_F(DcSyncTest, SingleShot) {
  const std::uint64_t start = now_system() + 1'000'000;
  program(start, 0, 0, kActivateSyncUnit | kActivateSync0);
  run_until(now + ms(20));
  ASSERT_EQ(rec.rising(0).size(), 1u);
  expect_at(rec.rising(0), start, 0);
}

TEST_F(DcSyncTest, Sync1ShiftedFromSync0) {
  const std::uint64_t start = now_system() + 1'000'000;
  program(start, 1'000'000, 300'000, kActivateSyncUnit | kActivateSync0 | kActivateSync1);
  EXPECT_EQ(dc_read(dc, kNextSync1Pulse, 8, now), start + 300'000);
  run_until(now + ms(6) + us(500));
  ASSERT_EQ(rec.rising(1).size(), 6u);
  expect_at(rec.rising(1), start + 300'000, 1'000'000);
}

TEST_F(DcSyncTest, Sync1AsMultipleOfSync0) {
  const std::uint64_t start = now_system() + 1'000'000;
  program(start, 1'000'000, 3'000'000, kActivateSyncUnit | kActivateSync0 | kActivateSync1);
  EXPECT_EQ(dc_read(dc, kNextSync1Pulse, 8, now), start + 3'000'000);
  run_until(now + ms(10) + us(500));
  ASSERT_EQ(rec.rising(0).size(), 10u);
  ASSERT_EQ(rec.rising(1).size(), 3u);
  expect_at(rec.rising(1), start + 3'000'000, 3'000'000);
}

TEST_F(DcSyncTest, Sync1CycleZeroMirrorsSync0) {
  const std::uint64_t start = now_system() + 1'000'000;
  program(start, 500'000, 0, kActivateSyncUnit | kActivateSync1);  // SYNC0 output off
  run_until(now + ms(3) - us(100));
  EXPECT_TRUE(rec.rising(0).empty());
  ASSERT_EQ(rec.rising(1).size(), 4u);
  expect_at(rec.rising(1), start, 500'000);
}

TEST_F(DcSyncTest, AcknowledgeModeHoldsUntilPdiReadsStatus) {
  init(0);
  const std::uint64_t start = now_system() + 1'000'000;
  program(start, 1'000'000, 0, kActivateSyncUnit | kActivateSync0);
  run_until(now + ms(1) + us(10));
  EXPECT_TRUE(dc.sync_output(0));
  EXPECT_EQ(dc.al_event_request() & kAlEventSync0, kAlEventSync0);
  EXPECT_EQ(dc_read(dc, kSync0Status, 1, now), 1u);  // ECAT read does not acknowledge
  EXPECT_TRUE(dc.sync_output(0));
  EXPECT_EQ(dc_read(dc, kSync0Status, 1, now, Side::Pdi), 1u);
  EXPECT_FALSE(dc.sync_output(0));
  EXPECT_EQ(dc.al_event_request() & kAlEventSync0, 0u);
  EXPECT_EQ(dc_read(dc, kSync0Status, 1, now, Side::Pdi), 0u);
}

TEST_F(DcSyncTest, StartTimeInThePastNeverFires) {
  program(now_system() - 1000, 1'000'000, 0, kActivateSyncUnit | kActivateSync0);
  run_until(now + ms(20));
  EXPECT_TRUE(rec.rising(0).empty());
  EXPECT_EQ(dc_read(dc, kActivationStatus, 1, now), kFirstSync0Pending);
}

TEST_F(DcSyncTest, PlausibilityCheckFiresAtOnceAndFlagsIt) {
  const std::uint64_t past = now_system() - 1000;
  program(past, 1'000'000, 0, kActivateSyncUnit | kActivateSync0 | kStartTimePlausibility);
  EXPECT_EQ(dc_read(dc, kActivationStatus, 1, now) & kStartTimeOutOfNearFuture, kStartTimeOutOfNearFuture);
  run_until(now + ms(2) + us(500));
  EXPECT_EQ(rec.rising(0).size(), 3u);
}

TEST_F(DcSyncTest, DeactivationStopsPulses) {
  program(now_system() + 1'000'000, 1'000'000, 0, kActivateSyncUnit | kActivateSync0);
  run_until(now + ms(3) + us(500));
  EXPECT_EQ(rec.rising(0).size(), 3u);
  dc_write(dc, kActivation, 0, 1, now);
  run_until(now + ms(5));
  EXPECT_EQ(rec.rising(0).size(), 3u);
}

TEST_F(DcSyncTest, OnlyTheOwnerProgramsTheSyncUnit) {
  dc_write(dc, kCyclicUnitControl, kSyncOwnerPdi, 1, now);
  dc_write(dc, kActivation, kActivateSyncUnit | kActivateSync0, 1, now);
  EXPECT_EQ(dc_read(dc, kActivation, 1, now), 0u);
  dc_write(dc, kSync0CycleTime, 1'000'000, 4, now, Side::Pdi);
  dc_write(dc, kStartTimeCyclicOperation, now_system() + 1'000'000, 8, now, Side::Pdi);
  dc_write(dc, kActivation, kActivateSyncUnit | kActivateSync0, 1, now, Side::Pdi);
  run_until(now + ms(2) + us(500));
  EXPECT_EQ(rec.rising(0).size(), 2u);
}

TEST_F(DcSyncTest, AutoActivationWith32BitStartTime) {
  dc_write(dc, kSync0CycleTime, 1'000'000, 4, now);
  dc_write(dc, kActivation, kActivateSync0 | kAutoActivation | kStartTimeExtension, 1, now);
  const std::uint64_t start = now_system() + 2'000'000;
  dc_write(dc, kStartTimeCyclicOperation, start & 0xFFFF'FFFFu, 4, now);
  EXPECT_EQ(dc_read(dc, kActivation, 1, now) & kActivateSyncUnit, kActivateSyncUnit);
  EXPECT_EQ(dc_read(dc, kStartTimeCyclicOperation, 8, now), start);
  run_until(now + ms(3) + us(500));
  ASSERT_EQ(rec.rising(0).size(), 2u);
  expect_at(rec.rising(0), start, 1'000'000);
}

TEST_F(DcSyncTest, DebugPulseClearsItself) {
  dc_write(dc, kActivation, kActivateSync0 | kDebugPulse, 1, now);
  EXPECT_EQ(rec.rising(0).size(), 1u);
  EXPECT_EQ(dc_read(dc, kActivation, 1, now), kActivateSync0);
}

TEST_F(DcSyncTest, LatchSingleEventKeepsFirstEdgeUntilRead) {
  dc_write(dc, kLatch0Control, kLatchPositiveSingle, 1, now);
  dc.set_latch_input(0, true, now + us(5));
  const std::uint64_t first = dc.system_time(now + us(5));
  dc.set_latch_input(0, false, now + us(6));
  dc.set_latch_input(0, true, now + us(7));
  EXPECT_EQ(dc_read(dc, kLatch0Status, 1, now + us(8)),
            kLatchPositiveEvent | kLatchNegativeEvent | kLatchPinState);
  EXPECT_EQ(dc.ecat_event_request() & kEcatEventLatch, kEcatEventLatch);
  EXPECT_EQ(dc_read(dc, kLatch0TimePositive, 8, now + us(8)), first);
  EXPECT_EQ(dc_read(dc, kLatch0TimeNegative, 8, now + us(8)), dc.system_time(now + us(6)));
  EXPECT_EQ(dc_read(dc, kLatch0Status, 1, now + us(8)), kLatchPinState);
  EXPECT_EQ(dc.ecat_event_request() & kEcatEventLatch, 0u);
}

// A pending latch event goes to the owner 0x0980 names as soon as it is
// written (Section II 0x0980 bits 4/5), not at the next DC register read.
TEST_F(DcSyncTest, LatchEventFollowsTheOwnerAsItIsWritten) {
  dc.set_latch_input(0, true, now + us(1));
  ASSERT_NE(dc.ecat_event_request() & kEcatEventLatch, 0u);
  ASSERT_EQ(dc.al_event_request() & kAlEventLatch, 0u);
  dc_write(dc, kCyclicUnitControl, kLatch0OwnerPdi, 1, now + us(2));
  EXPECT_EQ(dc.ecat_event_request() & kEcatEventLatch, 0u);
  EXPECT_NE(dc.al_event_request() & kAlEventLatch, 0u);
  dc_write(dc, kCyclicUnitControl, 0, 1, now + us(3));
  EXPECT_NE(dc.ecat_event_request() & kEcatEventLatch, 0u);
  EXPECT_EQ(dc.al_event_request() & kAlEventLatch, 0u);
}

TEST_F(DcSyncTest, LatchContinuousOverwritesAndPdiOwnerGetsAlEvent) {
  dc_write(dc, kCyclicUnitControl, kLatch1OwnerPdi, 1, now);
  dc.set_latch_input(1, true, now + us(1));
  dc.set_latch_input(1, false, now + us(2));
  dc.set_latch_input(1, true, now + us(3));
  EXPECT_EQ(dc.al_event_request() & kAlEventLatch, kAlEventLatch);
  (void)dc_read(dc, kLatch1TimePositive, 8, now + us(4));  // ECAT is not the owner
  EXPECT_EQ(dc.al_event_request() & kAlEventLatch, kAlEventLatch);
  EXPECT_EQ(dc_read(dc, kLatch1TimePositive, 8, now + us(4), Side::Pdi), dc.system_time(now + us(3)));
  EXPECT_EQ(dc_read(dc, kLatch1TimeNegative, 8, now + us(4), Side::Pdi), dc.system_time(now + us(2)));
  EXPECT_EQ(dc.al_event_request() & kAlEventLatch, 0u);
}

// A read renders only the registers it covers (DcUnit::render): every
// range of 1, 2, 4 and 8 bytes of the block reads as the same bytes of one
// read of the whole block at the same time, on both sides, with the SYNC
// units running, the time loop's registers, a SYNC1 schedule and latch
// events set. The PDI reads leave 0x098E on out (reading the SYNC status
// acknowledges it, the latch times clear their events).
TEST_F(DcSyncTest, EveryRangeReadsAsTheWholeBlock) {
  init(0);  // acknowledge mode: the status bytes hold until read
  const std::uint64_t start = now_system() + 2'000'000;
  program(start, 1'000'000, 250'000, kActivateSyncUnit | kActivateSync0 | kActivateSync1);
  for (int k = 0; k < 5; ++k) {  // the time loop runs: its difference and speed counter registers show values
    dc_write(dc, kSystemTime, now_system() - 100'000, 4, now);
    run_until(now + ms(1));
  }
  run_until(now + us(300));
  // A difference past 16 bits and a negative speed counter difference: every byte of both shows.
  ASSERT_EQ(dc_read(dc, kSystemTimeDifference, 4, now), 100'000u);
  ASSERT_GE(dc_read(dc, kSpeedCounterDiff, 2, now), 0x8000u);
  // Latch events and pin levels, owned by the PDI so that ECAT reads of
  // their times clear nothing (the PDI loop stops before 0x098E).
  dc_write(dc, kCyclicUnitControl, kLatch0OwnerPdi | kLatch1OwnerPdi, 1, now);
  dc.set_latch_input(0, true, now - us(5));
  dc.set_latch_input(0, false, now - us(4));
  dc.set_latch_input(0, true, now - us(3));
  dc.set_latch_input(1, true, now - us(2));
  dc.set_latch_input(1, false, now - us(1));
  for (const Side side : {Side::Ecat, Side::Pdi}) {
    std::array<std::uint8_t, DcUnit::kSize> whole{};
    const std::uint16_t end = side == Side::Pdi ? kSync0Status : DcUnit::kSize;
    dc.read(0, std::span<std::uint8_t>(whole.data(), end), now, side);
    for (const std::size_t size : {1u, 2u, 4u, 8u}) {
      for (std::uint16_t at = 0; at + size <= end; ++at) {
        std::array<std::uint8_t, 8> part{};
        dc.read(at, std::span<std::uint8_t>(part.data(), size), now, side);
        for (std::size_t k = 0; k < size; ++k) {
          ASSERT_EQ(part[k], whole[at + k]) << "side " << static_cast<int>(side) << ", 0x" << std::hex
                                            << 0x0900 + at + k << " in a read of " << std::dec << size << " at 0x"
                                            << std::hex << 0x0900 + at;
        }
      }
    }
  }
  EXPECT_NE(dc_read(dc, kSync0Status, 1, now), 0u);  // pulses were latched, so the status was in the block
  EXPECT_NE(dc_read(dc, kStartTimeCyclicOperation, 8, now), 0u);
  EXPECT_NE(dc_read(dc, kLatch0Status, 1, now), 0u);
  for (const std::uint16_t time :
       {kLatch0TimePositive, kLatch0TimeNegative, kLatch1TimePositive, kLatch1TimeNegative}) {
    EXPECT_NE(dc_read(dc, time, 8, now), 0u);
  }
}

}  // namespace
}  // namespace ecat::esc::test
