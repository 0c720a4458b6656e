// The master's cycle as the slaves see it (slave/cycle_timing.hpp, issue 27
// item 2's lateness histogram): where a cycle starts, the period as the
// median interval, the buckets at their exact edges, the ring overrun, the
// first logical address taken from the frame, and the chain counting the
// in-process master's cycles with one made late and one missed.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <vector>

#include "common/frame_builder.hpp"
#include "slave/cycle_timing.hpp"
#include "slave/frame_tally.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

using slave::CycleTiming;
using std::chrono::microseconds;
using std::chrono::milliseconds;

constexpr std::int64_t kPeriod = 1'000'000;  // 1 ms in ns

TEST(CycleTiming, BucketsAtTheirExactEdges) {
  // (interval - period) in % of the period; upper bounds exclusive, on time inclusive.
  EXPECT_EQ(CycleTiming::bucket_of(899'999, kPeriod), CycleTiming::Early);
  EXPECT_EQ(CycleTiming::bucket_of(900'000, kPeriod), CycleTiming::OnTime);   // -10 %
  EXPECT_EQ(CycleTiming::bucket_of(1'100'000, kPeriod), CycleTiming::OnTime); // +10 %
  EXPECT_EQ(CycleTiming::bucket_of(1'100'001, kPeriod), CycleTiming::Late10);
  EXPECT_EQ(CycleTiming::bucket_of(1'249'999, kPeriod), CycleTiming::Late10);
  EXPECT_EQ(CycleTiming::bucket_of(1'250'000, kPeriod), CycleTiming::Late25);
  EXPECT_EQ(CycleTiming::bucket_of(1'499'999, kPeriod), CycleTiming::Late25);
  EXPECT_EQ(CycleTiming::bucket_of(1'500'000, kPeriod), CycleTiming::Missed1);  // 2 periods +- 1/2
  EXPECT_EQ(CycleTiming::bucket_of(2'000'000, kPeriod), CycleTiming::Missed1);
  EXPECT_EQ(CycleTiming::bucket_of(2'499'999, kPeriod), CycleTiming::Missed1);
  EXPECT_EQ(CycleTiming::bucket_of(2'500'000, kPeriod), CycleTiming::Missed2);
  EXPECT_EQ(CycleTiming::bucket_of(0, kPeriod), CycleTiming::Early);
  // An hour's interval at a 1 ms period: no overflow.
  EXPECT_EQ(CycleTiming::bucket_of(std::int64_t{3'600} * 1'000'000'000, kPeriod), CycleTiming::Missed2);
}

TEST(CycleTiming, ACycleStartsWhereTheLogicalAddressesStartOver) {
  CycleTiming t;
  // Three frames per cycle (addresses 0, 0x600, 0xC00), cycles 1 ms apart,
  // the frames 20 us apart within a cycle.
  for (int c = 0; c < 5; ++c) {
    const Nanoseconds start = milliseconds(c);
    t.on_frame(start, 0x0000);
    t.on_frame(start + microseconds(20), 0x0600);
    t.on_frame(start + microseconds(40), 0x0C00);
  }
  EXPECT_EQ(t.cycles(), 5u);
  t.settle();
  EXPECT_EQ(t.period(), milliseconds(1));
  EXPECT_EQ(t.buckets()[CycleTiming::OnTime], 4u);  // 4 intervals between 5 starts
  // One frame per cycle at one address: every frame starts a cycle.
  CycleTiming one;
  for (int c = 0; c < 4; ++c) one.on_frame(microseconds(500 * c), 0x00010000);
  EXPECT_EQ(one.cycles(), 4u);
  one.settle();
  EXPECT_EQ(one.period(), microseconds(500));
}

TEST(CycleTiming, ThePeriodIsTheMedianAndEachIntervalIsSortedOnce) {
  CycleTiming t;
  Nanoseconds at{0};
  // 20 on-time intervals, then one 1.3 ms (late 30 %), one 0.7 ms (early),
  // one 2 ms (a cycle missed), one 3 ms (two missed).
  t.on_frame(at, 0);
  for (int k = 0; k < 20; ++k) t.on_frame(at += milliseconds(1), 0);
  for (const auto d : {microseconds(1300), microseconds(700), microseconds(2000), microseconds(3000)}) {
    t.on_frame(at += d, 0);
  }
  t.settle();
  EXPECT_EQ(t.period(), milliseconds(1));
  const std::array<std::uint64_t, CycleTiming::kBuckets> expected{1, 20, 0, 1, 1, 1};
  EXPECT_EQ(t.buckets(), expected);
  t.settle();  // nothing new: nothing counted twice
  EXPECT_EQ(t.buckets(), expected);
  t.on_frame(at += milliseconds(1), 0);
  t.settle();
  EXPECT_EQ(t.buckets()[CycleTiming::OnTime], 21u);
  EXPECT_EQ(t.unsorted(), 0u);
}

// Once the window is full the period is taken again only when the window
// has been renewed: a master that halves its cycle time is seen as early
// cycles until kMedianWindow of the new intervals have come.
TEST(CycleTiming, ThePeriodIsTakenAgainOnceTheWindowIsRenewed) {
  CycleTiming t;
  Nanoseconds at{0};
  const auto add = [&](std::size_t n, Nanoseconds d) {
    for (std::size_t k = 0; k < n; ++k) t.on_frame(at += d, 0);
  };
  t.on_frame(at, 0);
  add(CycleTiming::kMedianWindow, milliseconds(1));
  t.settle();
  EXPECT_EQ(t.period(), milliseconds(1));
  add(200, microseconds(500));
  t.settle();  // 200 new: the period stays, the 200 are early against it
  EXPECT_EQ(t.period(), milliseconds(1));
  EXPECT_EQ(t.buckets()[CycleTiming::Early], 200u);
  add(CycleTiming::kMedianWindow - 200, microseconds(500));
  t.settle();  // the window renewed: its median is the new period
  EXPECT_EQ(t.period(), microseconds(500));
  EXPECT_EQ(t.buckets()[CycleTiming::OnTime], CycleTiming::kMedianWindow + CycleTiming::kMedianWindow - 200);
}

// A master whose every interval stays within +-10 % of the period keeps
// the period: no new median (its selection was the page's cost); one
// interval outside that band and a renewed window take it again.
TEST(CycleTiming, AWindowWhollyOnTimeKeepsThePeriod) {
  CycleTiming t;
  Nanoseconds at{0};
  const auto add = [&](std::size_t n, Nanoseconds d) {
    for (std::size_t k = 0; k < n; ++k) t.on_frame(at += d, 0);
  };
  t.on_frame(at, 0);
  add(CycleTiming::kMedianWindow, milliseconds(1));
  t.settle();
  ASSERT_EQ(t.period(), milliseconds(1));
  add(CycleTiming::kMedianWindow, microseconds(1'080));  // +8 %: on time
  t.settle();
  EXPECT_EQ(t.period(), milliseconds(1));
  EXPECT_EQ(t.buckets()[CycleTiming::OnTime], 2 * CycleTiming::kMedianWindow);
  add(1, microseconds(1'200));  // late
  add(CycleTiming::kMedianWindow - 1, microseconds(1'080));
  t.settle();  // the late one came in a window that is not yet renewed: sorted, period kept
  EXPECT_EQ(t.period(), milliseconds(1));
  EXPECT_EQ(t.buckets()[CycleTiming::Late10], 1u);
  add(CycleTiming::kMedianWindow, microseconds(1'080));
  t.settle();  // renewed, and not every interval was on time: the median again
  EXPECT_EQ(t.period(), microseconds(1'080));
  EXPECT_EQ(t.buckets()[CycleTiming::OnTime], 4 * CycleTiming::kMedianWindow - 1);
}

// The edges in nanoseconds give what interval * 100 against period * (100
// + percent) gives, for a period that 100 does not divide.
TEST(CycleTiming, BucketEdgesAreExactForAnyPeriod) {
  constexpr std::int64_t kOdd = 1'000'003;  // 90 % = 900002.7, 110 % = 1100003.3, 125 % = 1250003.75
  EXPECT_EQ(CycleTiming::bucket_of(900'002, kOdd), CycleTiming::Early);
  EXPECT_EQ(CycleTiming::bucket_of(900'003, kOdd), CycleTiming::OnTime);
  EXPECT_EQ(CycleTiming::bucket_of(1'100'003, kOdd), CycleTiming::OnTime);
  EXPECT_EQ(CycleTiming::bucket_of(1'100'004, kOdd), CycleTiming::Late10);
  EXPECT_EQ(CycleTiming::bucket_of(1'250'003, kOdd), CycleTiming::Late10);
  EXPECT_EQ(CycleTiming::bucket_of(1'250'004, kOdd), CycleTiming::Late25);
  EXPECT_EQ(CycleTiming::bucket_of(2'500'007, kOdd), CycleTiming::Missed1);  // 250 % = 2500007.5
  EXPECT_EQ(CycleTiming::bucket_of(2'500'008, kOdd), CycleTiming::Missed2);
}

TEST(CycleTiming, IntervalsOverwrittenBeforeASettleAreCountedUnsorted) {
  CycleTiming t;
  const std::size_t extra = 10;
  for (std::size_t k = 0; k <= CycleTiming::kRing + extra; ++k) t.on_frame(microseconds(250 * k), 0);
  t.settle();
  EXPECT_EQ(t.unsorted(), extra);
  EXPECT_EQ(t.buckets()[CycleTiming::OnTime], CycleTiming::kRing);
  EXPECT_EQ(t.period(), microseconds(250));
}

TEST(CycleTiming, FramesAtOneInstantHaveNoPeriodToJudgeBy) {
  CycleTiming t;
  for (int k = 0; k < 3; ++k) t.on_frame(milliseconds(1), 0);
  t.settle();
  EXPECT_EQ(t.period(), Nanoseconds{0});
  EXPECT_EQ(t.unsorted(), 2u);
  EXPECT_EQ(t.buckets(), (std::array<std::uint64_t, CycleTiming::kBuckets>{}));
}

TEST(FrameTally, TakesTheAddressOfTheFirstLogicalDatagram) {
  std::array<std::uint8_t, kMinEthernetFrame * 2> buffer{};
  FrameBuilder b(buffer);
  ASSERT_TRUE(b.append_zeros(Command::Fprd, 0, 0x01300003, 2));
  ASSERT_TRUE(b.append_zeros(Command::Lrw, 1, 0x00012345, 8));
  ASSERT_TRUE(b.append_zeros(Command::Lrd, 2, 0x00000010, 4));
  const auto frame = b.finish();
  const slave::FrameTally t = slave::tally_frame(frame);
  EXPECT_EQ(t.datagrams, 3u);
  EXPECT_TRUE(t.logical);
  EXPECT_EQ(t.first_logical, 0x00012345u);
  std::array<std::uint8_t, kMinEthernetFrame * 2> buffer2{};
  FrameBuilder none(buffer2);
  ASSERT_TRUE(none.append_zeros(Command::Brd, 0, 0x01300000, 2));
  const auto f2 = none.finish();
  EXPECT_FALSE(slave::tally_frame(f2).logical);
}

TEST(CycleTiming, TheChainCountsTheMastersCyclesWithOneLateAndOneMissed) {
  InProcess p;
  p.add_default(2);
  ASSERT_EQ(p.bring_up(), "");
  slave::CycleTiming& timing = p.chain.cycle_timing();
  const std::uint64_t before = timing.cycles();
  ASSERT_GE(before, 10u);  // bring_up's 10 cycles in SafeOp
  for (int c = 0; c < 30; ++c) ASSERT_TRUE(p.cycle_once(milliseconds(1)));
  ASSERT_TRUE(p.cycle_once(microseconds(1400)));  // late: 40 % of the period
  ASSERT_TRUE(p.cycle_once(milliseconds(2)));     // one cycle missed
  ASSERT_TRUE(p.cycle_once(milliseconds(1)));
  EXPECT_EQ(timing.cycles(), before + 33);
  timing.settle();
  // Each exchange is one LRW frame; between two of them the wire time of
  // the master's other frames passes too, the same every cycle.
  const Nanoseconds period = timing.period();
  EXPECT_GE(period, milliseconds(1));
  EXPECT_LT(period, milliseconds(1) + microseconds(50));
  EXPECT_EQ(timing.buckets()[CycleTiming::Late25], 1u);
  EXPECT_EQ(timing.buckets()[CycleTiming::Missed1], 1u);
}

}  // namespace
}  // namespace ecat::test
