// Profile position mode: trapezoid with 6081h/6083h/6084h, set-point
// handshake, buffer, relative targets, change set immediately, halt, limits.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

#include "ds402/controlword.hpp"
#include "ds402/statusword.hpp"
#include "harness.hpp"

namespace ecat::ds402::test {
namespace {

constexpr std::uint16_t kEnableOp = 0x000F;
constexpr std::uint16_t kNewSp = kEnableOp | cw::kNewSetPoint;

struct Pp : ::testing::Test {
  Harness h;
  void SetUp() override {
    h.in.profile_velocity = 100000;       // increments/s
    h.in.profile_acceleration = 1000000;  // increments/s²
    h.in.profile_deceleration = 500000;
    h.in.position_window = 100;
    h.enable(OperationMode::ProfilePosition);
    ASSERT_EQ(h.drive.state(), PdsState::OperationEnabled);
    ASSERT_EQ(h.out.modes_of_operation_display, 1);
  }
  // Bit 4 up until acknowledged, then down.
  bool send(std::int32_t target, std::uint16_t extra = 0) {
    h.in.target_position = target;
    h.command(kNewSp | extra);
    const bool ack = h.bit(sw::kSetPointAcknowledge);
    h.command(kEnableOp | (extra & ~cw::kNewSetPoint));
    return ack;
  }
  int until_reached(int limit) {
    return h.run_until([&] { return h.bit(sw::kTargetReached); }, limit);
  }
};

TEST_F(Pp, TrapezoidUsesProfileVelocityAndAcceleration) {
  EXPECT_TRUE(h.bit(sw::kTargetReached));  // nothing to do yet
  h.in.target_position = 200000;
  h.command(kNewSp);
  EXPECT_TRUE(h.bit(sw::kSetPointAcknowledge));
  EXPECT_FALSE(h.bit(sw::kTargetReached));
  h.command(kEnableOp);
  EXPECT_FALSE(h.bit(sw::kSetPointAcknowledge));  // released: ready for the next one
  // 2 cycles of 1 ms at 1e6 inc/s² -> demand velocity 2000 inc/s after the
  // first step, then +1000 per cycle.
  h.run(48);
  EXPECT_EQ(h.out.velocity_demand, 50000);
  std::int32_t vmax = 0;
  const int cycles = h.run_until(
      [&] {
        vmax = std::max(vmax, h.out.velocity_demand);
        return h.bit(sw::kTargetReached);
      },
      5000);
  EXPECT_EQ(vmax, 100000);
  // Analytic: accel 0.1 s, cruise, decel 0.2 s: 0.05 + 1.85 + 0.1 ... = 2.15 s
  // of demand, plus the position loop settling into the 100-increment window.
  const int total = cycles + 50;
  EXPECT_GE(total, 2150);
  EXPECT_LE(total, 2250);
  EXPECT_LE(std::abs(h.out.position_actual - 200000), 100);
  EXPECT_EQ(h.out.position_demand, 200000);
}

TEST_F(Pp, DecelerationPhaseUsesProfileDeceleration) {
  h.in.target_position = 100000;
  h.command(kNewSp);
  h.command(kEnableOp);
  // Find the first cycle the demand velocity falls below the profile velocity.
  std::int32_t previous = 0;
  h.run_until(
      [&] {
        const bool falling = h.out.velocity_demand < previous && previous == 100000;
        previous = h.out.velocity_demand;
        return falling;
      },
      3000);
  const std::int32_t v0 = h.out.velocity_demand;
  h.run(100);
  EXPECT_NEAR(v0 - h.out.velocity_demand, 50000, 600);  // 0.1 s at 5e5 inc/s²
}

TEST_F(Pp, RelativeTargetsAddUp) {
  EXPECT_TRUE(send(30000, cw::kRelative));
  ASSERT_GT(until_reached(3000), 0);
  EXPECT_TRUE(send(30000, cw::kRelative));
  ASSERT_GT(until_reached(3000), 0);
  EXPECT_NEAR(h.out.position_actual, 60000, 100);
  EXPECT_EQ(h.out.position_demand, 60000);
}

TEST_F(Pp, BufferedSetPointRunsAfterTheFirst) {
  EXPECT_TRUE(send(50000));
  h.run(10);
  EXPECT_TRUE(send(-20000));  // buffered
  // Buffer full: a third set-point is not acknowledged.
  h.in.target_position = 99999;
  h.command(kNewSp);
  EXPECT_TRUE(h.bit(sw::kSetPointAcknowledge));  // still 1: buffer full
  h.command(kEnableOp);
  EXPECT_TRUE(h.bit(sw::kSetPointAcknowledge));
  // The first move ends at 50000 before the second starts.
  std::int32_t peak = 0;
  ASSERT_GT(h.run_until(
                [&] {
                  peak = std::max(peak, h.out.position_demand);
                  return h.bit(sw::kTargetReached);
                },
                5000),
            0);
  EXPECT_EQ(peak, 50000);
  EXPECT_EQ(h.out.position_demand, -20000);
  EXPECT_NEAR(h.out.position_actual, -20000, 100);
  EXPECT_FALSE(h.bit(sw::kSetPointAcknowledge));
}

TEST_F(Pp, ChangeOnSetPointPassesTheFirstTargetWithoutStopping) {
  EXPECT_TRUE(send(50000, cw::kChangeOnSetPoint));
  EXPECT_TRUE(send(120000, cw::kChangeOnSetPoint));
  std::int32_t vmin_after_start = 1 << 30;
  bool started = false;
  std::int32_t at_first = -1;
  ASSERT_GT(h.run_until(
                [&] {
                  if (h.out.velocity_demand == 100000) started = true;  // cruising
                  if (started && h.out.position_demand < 110000)
                    vmin_after_start = std::min(vmin_after_start, h.out.velocity_demand);
                  if (at_first < 0 && h.out.position_demand >= 50000) at_first = h.out.velocity_demand;
                  return h.bit(sw::kTargetReached);
                },
                5000),
            0);
  EXPECT_EQ(at_first, 100000);          // passes 50000 at the profile velocity
  EXPECT_EQ(vmin_after_start, 100000);  // never slows before the last braking
  EXPECT_EQ(h.out.position_demand, 120000);
}

TEST_F(Pp, ChangeOnSetPointStopsWhenTheNextMoveReverses) {
  EXPECT_TRUE(send(50000, cw::kChangeOnSetPoint));
  EXPECT_TRUE(send(10000, cw::kChangeOnSetPoint));
  std::int32_t peak = 0;
  ASSERT_GT(h.run_until(
                [&] {
                  peak = std::max(peak, h.out.position_demand);
                  return h.bit(sw::kTargetReached);
                },
                5000),
            0);
  EXPECT_EQ(peak, 50000);
  EXPECT_EQ(h.out.position_demand, 10000);
}

TEST_F(Pp, ChangeSetImmediatelyReplacesTheMove) {
  EXPECT_TRUE(send(200000));
  h.run(300);
  EXPECT_GT(h.out.position_demand, 20000);
  EXPECT_TRUE(send(10000, cw::kChangeSetImmediately));
  std::int32_t peak = 0;
  ASSERT_GT(h.run_until(
                [&] {
                  peak = std::max(peak, h.out.position_demand);
                  return h.bit(sw::kTargetReached);
                },
                5000),
            0);
  EXPECT_LT(peak, 60000);  // turned round long before 200000
  EXPECT_EQ(h.out.position_demand, 10000);
}

TEST_F(Pp, HaltStopsAndResumes) {
  EXPECT_TRUE(send(150000));
  h.run(500);
  h.command(kEnableOp | cw::kHalt);
  ASSERT_GT(h.run_until([&] { return h.bit(sw::kTargetReached); }, 1000), 0);  // halted: speed 0
  const std::int32_t stopped_at = h.out.position_demand;
  h.run(100);
  EXPECT_EQ(h.out.position_demand, stopped_at);
  EXPECT_LT(stopped_at, 150000);
  h.command(kEnableOp);
  ASSERT_GT(until_reached(5000), 0);
  EXPECT_EQ(h.out.position_demand, 150000);
}

TEST_F(Pp, SoftwareLimitClipsTheTarget) {
  h.in.software_limit_min = -40000;
  h.in.software_limit_max = 40000;
  h.in.target_position = 90000;
  h.command(kNewSp);
  EXPECT_TRUE(h.bit(sw::kInternalLimitActive));
  h.command(kEnableOp);
  ASSERT_GT(until_reached(5000), 0);
  EXPECT_EQ(h.out.position_demand, 40000);
}

TEST_F(Pp, PositionWindowTimeDelaysTargetReached) {
  h.in.position_window_time = 20;  // ms
  EXPECT_TRUE(send(1000));
  const int plain = until_reached(3000);
  ASSERT_GT(plain, 0);
  EXPECT_TRUE(send(2000));
  int inside = -1;
  int reached = -1;
  for (int i = 1; i < 3000 && reached < 0; ++i) {
    h.step();
    if (inside < 0 && std::abs(h.out.position_actual - 2000) <= 100 && h.out.position_demand == 2000) inside = i;
    if (h.bit(sw::kTargetReached)) reached = i;
  }
  ASSERT_GT(inside, 0);
  EXPECT_GE(reached - inside, 19);
}

}  // namespace
}  // namespace ecat::ds402::test
