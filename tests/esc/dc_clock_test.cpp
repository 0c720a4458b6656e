// Local clock model and the basic DC registers: reset values, system time
// and offset, delay on ECAT reads, receive-time latches, 0x092C encoding.
#include <gtest/gtest.h>

#include <cmath>

#include "dc_fixture.hpp"
#include "esc/dc/local_clock.hpp"
#include "esc/dc/time_loop.hpp"

namespace ecat::esc::test {
namespace {

using namespace dcreg;

TEST(LocalClock, RunsAtItsOwnRate) {
  LocalClock fast(100.0, 5000);
  EXPECT_EQ(fast.at(Nanoseconds{0}), 5000u);
  EXPECT_EQ(fast.at(ms(1000)), 5000u + 1'000'100'000u);  // +100 µs per second
  LocalClock slow(-100.0, 0);
  EXPECT_EQ(slow.at(ms(1000)), 999'900'000u);
}

TEST(LocalClock, WhenInvertsAt) {
  LocalClock c(-73.0, 123456789);
  for (std::uint64_t local : {123456789ull, 123456790ull, 200000000ull, 987654321012ull}) {
    const Nanoseconds t = c.when(local);
    EXPECT_GE(c.at(t), local);
    EXPECT_LT(c.at(t - Nanoseconds{1}), local);
  }
}

TEST(LocalClock, RateCorrectionKeepsTimeContinuous) {
  LocalClock c(100.0, 0);
  const std::uint64_t before = c.at(ms(10));
  c.set_rate_correction(ms(10), -100e-6);
  EXPECT_EQ(c.at(ms(10)), before);
  EXPECT_NEAR(static_cast<double>(c.at(ms(1010)) - before), 1e9, 1.0);  // now exactly 1 ns/ns
}

// A settled time loop sets the same correction at every ESC every DC
// cycle: the clock answers as one that was set once - exactly while it
// keeps its anchor, within 1 ns after it moved it (every kReanchorNs) -
// and a new correction takes effect at once.
TEST(LocalClock, AnUnchangedCorrectionKeepsTheSameLine) {
  constexpr double kCorrection = 2e-5;
  LocalClock once(37.0, 123'456);
  LocalClock every(37.0, 123'456);
  once.set_rate_correction(ms(1), kCorrection);
  every.set_rate_correction(ms(1), kCorrection);
  for (Nanoseconds t = ms(1); t < ms(10'000); t += ms(1)) {
    every.set_rate_correction(t, kCorrection);
    const Nanoseconds ahead = t + us(500);
    const auto diff = static_cast<std::int64_t>(every.at(ahead) - once.at(ahead));
    if ((t - ms(1)).count() < LocalClock::kReanchorNs) {
      ASSERT_EQ(diff, 0) << t.count();
      ASSERT_EQ(every.when(once.at(ahead)), once.when(once.at(ahead))) << t.count();
    } else {
      ASSERT_LE(std::abs(diff), 1) << t.count();
    }
  }
  const Nanoseconds t = ms(10'000);
  const std::uint64_t before = every.at(t);
  every.set_rate_correction(t, -3e-5);
  EXPECT_EQ(every.at(t), before);
  EXPECT_NEAR(static_cast<double>(every.at(t + ms(1000)) - before), 1e9 * (1.0 + 37e-6 - 3e-5), 1.0);
}

// floor_to_int64 is std::floor for every value the clock meets: whole,
// just below and above a whole number, negative fractions.
TEST(LocalClock, FloorToInt64IsFloor) {
  for (const double x : {0.0, 0.25, 0.999999, 1.0, -0.25, -1.0, -1.5, 123456789.75, -987654321.125, 4e15 + 0.5,
                         -4e15 - 0.5}) {
    EXPECT_EQ(floor_to_int64(x), static_cast<std::int64_t>(std::floor(x))) << x;
  }
}

// The time loop's first comparison sets ē = e and the correction to
// -2ω·ē (ns -> s); the second moves ē by (e - ē) / 2^depth. ω and 1/2^depth
// are kept with their registers (restart, set_filter_depth): each value
// written must reach the next comparison.
TEST(TimeLoop, GainsFollowSpeedCounterStartAndFilterDepth) {
  const auto first_correction = [](std::uint16_t start) {
    TimeLoop loop;
    LocalClock clock;
    loop.restart(start);
    loop.compare(1000, ms(1), clock.at(ms(1)), clock);
    return clock.rate_correction();
  };
  EXPECT_DOUBLE_EQ(first_correction(0x1000), -2.0 * 20.0 * 1000.0 / 1e9);  // ω = 20 rad/s at reset
  EXPECT_DOUBLE_EQ(first_correction(0x2000), -2.0 * 10.0 * 1000.0 / 1e9);  // twice the start: half ω
  EXPECT_DOUBLE_EQ(first_correction(0x0800), -2.0 * 40.0 * 1000.0 / 1e9);
  EXPECT_DOUBLE_EQ(first_correction(0x0100), -2.0 * TimeLoop::kOmegaMax * 1000.0 / 1e9);  // at most kOmegaMax
  for (const std::uint8_t depth : {std::uint8_t{0}, std::uint8_t{2}, std::uint8_t{4}, std::uint8_t{15}}) {
    TimeLoop loop;
    LocalClock clock;
    loop.set_filter_depth(depth);
    loop.compare(1000, ms(1), clock.at(ms(1)), clock);
    loop.compare(3000, ms(2), clock.at(ms(2)), clock);
    EXPECT_DOUBLE_EQ(loop.filtered_difference(), 1000.0 + 2000.0 / static_cast<double>(1u << depth)) << int{depth};
  }
}

class DcUnitTest : public ::testing::Test {
 protected:
  DcUnitTest() {
    dc.set_clock(0.0, 1000);
    dc.reset(0x0000);
  }
  DcUnit dc;
};

TEST_F(DcUnitTest, ResetValues) {
  DcUnit other;
  other.reset(0x03E8);
  EXPECT_EQ(dc_read(other, kSpeedCounterStart, 2, Nanoseconds{0}), 0x1000u);
  EXPECT_EQ(dc_read(other, kSystemTimeDiffFilterDepth, 1, Nanoseconds{0}), 4u);
  EXPECT_EQ(dc_read(other, kSpeedCounterFilterDepth, 1, Nanoseconds{0}), 12u);
  EXPECT_EQ(dc_read(other, kSyncPulseLength, 2, Nanoseconds{0}), 0x03E8u);
  EXPECT_EQ(dc_read(other, kSystemTimeDifference, 4, Nanoseconds{0}), 0u);
}

TEST_F(DcUnitTest, SystemTimeIsLocalPlusOffsetAndEcatReadsSubtractTheDelay) {
  dc_write(dc, kSystemTimeOffset, 0x0000'0100'0000'0000ull, 8, us(1));
  dc_write(dc, kSystemTimeDelay, 700, 4, us(1));
  EXPECT_EQ(dc_read(dc, kSystemTime, 8, us(10), Side::Pdi), 0x0000'0100'0000'0000ull + 1000 + 10'000);
  EXPECT_EQ(dc_read(dc, kSystemTime, 8, us(10)), 0x0000'0100'0000'0000ull + 1000 + 10'000 - 700);
  EXPECT_EQ(dc_read(dc, kSystemTime, 4, us(10)), (1000u + 10'000u - 700u));  // low word
  EXPECT_EQ(dc_read(dc, kSystemTimeOffset, 8, us(10)), 0x0000'0100'0000'0000ull);
  EXPECT_EQ(dc_read(dc, kSystemTimeDelay, 4, us(10)), 700u);
}

TEST_F(DcUnitTest, PdiCannotWriteOffsetOrControl) {
  dc_write(dc, kSystemTimeOffset, 55, 8, us(1), Side::Pdi);
  dc_write(dc, kCyclicUnitControl, 1, 1, us(1), Side::Pdi);
  EXPECT_EQ(dc_read(dc, kSystemTimeOffset, 8, us(1)), 0u);
  EXPECT_EQ(dc_read(dc, kCyclicUnitControl, 1, us(1)), 0u);
}

TEST_F(DcUnitTest, WriteTo0x0900LatchesPortTimesOfThatFrame) {
  dc.on_frame_arrival(0, us(100));
  dc_write(dc, kReceiveTimePort0, 0, 4, us(100));
  dc.on_frame_arrival(1, us(100) + Nanoseconds{1234});
  EXPECT_EQ(dc_read(dc, kReceiveTimePort0, 4, us(200)), 101'000u);
  EXPECT_EQ(dc_read(dc, kReceiveTimePort0 + 4, 4, us(200)), 101'000u + 1234u);
  EXPECT_EQ(dc_read(dc, kReceiveTimeProcessingUnit, 8, us(200)), 101'000u);
  // A later frame without the 0x0900 write leaves the latches alone.
  dc.on_frame_arrival(0, us(300));
  dc.on_frame_arrival(1, us(301));
  EXPECT_EQ(dc_read(dc, kReceiveTimePort0 + 4, 4, us(400)), 101'000u + 1234u);
}

TEST_F(DcUnitTest, ReadOfReceiveTimesDoesNotLatch) {
  dc.on_frame_arrival(0, us(100));
  (void)dc_read(dc, kReceiveTimePort0, 4, us(100));
  EXPECT_EQ(dc_read(dc, kReceiveTimeProcessingUnit, 8, us(100)), 0u);
}

TEST_F(DcUnitTest, SystemTimeDifferenceIsSignAndMagnitude) {
  // Local copy at 10 µs = 11'000 (no offset); the master says 11'500: local behind.
  dc_write(dc, kSystemTime, 11'500, 8, us(10));
  EXPECT_EQ(dc_read(dc, kSystemTimeDifference, 4, us(10)), 0x8000'0000u | 500u);
  dc_write(dc, kSpeedCounterStart, 0x1000, 2, us(11));  // restarts the loop
  EXPECT_EQ(dc_read(dc, kSystemTimeDifference, 4, us(11)), 0u);
  // Local ahead by 300 (32-bit write compares the low word).
  dc_write(dc, kSystemTime, 12'000 - 300, 4, us(11));
  EXPECT_EQ(dc_read(dc, kSystemTimeDifference, 4, us(11)), 300u);
}

TEST_F(DcUnitTest, LoopSlowsAClockThatIsAhead) {
  dc_write(dc, kSystemTime, 11'000 - 2000, 8, us(10));  // local 2 µs ahead
  EXPECT_LT(dc.clock().rate_correction(), 0.0);
  // Stays 2 µs ahead for 10 ms: the frequency estimate (0x0932) goes negative.
  for (int k = 1; k <= 10; ++k) {
    const Nanoseconds t = us(10) + ms(k);
    dc_write(dc, kSystemTime, dc.system_time(t) - 2000, 8, t);
  }
  const auto speed = static_cast<std::int16_t>(dc_read(dc, kSpeedCounterDiff, 2, ms(11)));
  EXPECT_LT(speed, -10);
}

// A local time ~2^63 ns away (fuzz finding: a start time far from the local
// clock) is answered at the horizon instead of overflowing int64 time.
TEST(LocalClock, WhenFarAwayStaysInRange) {
  LocalClock c(0.0, 0);
  // Local time is modular: 2^63-1 ahead is the future, 2^63 ahead the past.
  const Nanoseconds future = c.when((std::uint64_t{1} << 63) - 1);
  EXPECT_GT(future.count(), std::int64_t{3'000'000'000'000'000'000});
  const Nanoseconds past = c.when(std::uint64_t{1} << 63);
  EXPECT_LT(past.count(), std::int64_t{-3'000'000'000'000'000'000});
  EXPECT_EQ(c.when(1000).count(), 1000);
}

// The local clock wraps at 2^64 (fuzz finding: a start time just past the
// wrap made when() walk backwards forever): 150 ns after a clock that
// started 100 ns before the wrap is local time 50.
TEST(LocalClock, WhenAcrossTheWrap) {
  LocalClock c(0.0, ~std::uint64_t{0} - 99);
  EXPECT_EQ(c.at(Nanoseconds{150}), 50u);
  EXPECT_EQ(c.when(50).count(), 150);
  EXPECT_EQ(c.when(~std::uint64_t{0}).count(), 99);
}

}  // namespace
}  // namespace ecat::esc::test
