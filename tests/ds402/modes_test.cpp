// Profile velocity, profile torque, the cyclic synchronous modes and mode
// switching in Operation enabled.
#include <gtest/gtest.h>

#include <cstdlib>

#include "ds402/controlword.hpp"
#include "ds402/statusword.hpp"
#include "harness.hpp"

namespace ecat::ds402::test {
namespace {

constexpr std::uint16_t kEnableOp = 0x000F;

TEST(ProfileVelocity, RampsToAndHoldsTheTarget) {
  Harness h;
  h.in.profile_acceleration = 1000000;
  h.in.profile_deceleration = 1000000;
  h.in.velocity_window = 2000;
  h.in.velocity_threshold = 500;
  h.enable(OperationMode::ProfileVelocity);
  EXPECT_TRUE(h.bit(sw::kSpeedZero));
  h.in.target_velocity = 200000;
  h.step();
  EXPECT_FALSE(h.bit(sw::kTargetReached));
  h.run(99);
  EXPECT_EQ(h.out.velocity_demand, 100000);  // 0.1 s at 1e6 inc/s²
  EXPECT_FALSE(h.bit(sw::kSpeedZero));
  const int cycles = h.run_until([&] { return h.bit(sw::kTargetReached); }, 1000);
  ASSERT_GT(cycles, 0);
  EXPECT_LE(cycles + 100, 230);
  h.run(500);
  EXPECT_TRUE(h.bit(sw::kTargetReached));
  EXPECT_NEAR(h.out.velocity_actual, 200000, 200);
  // Halt ramps to zero with 605Dh = 1 (6084h).
  h.command(kEnableOp | cw::kHalt);
  ASSERT_GT(h.run_until([&] { return h.out.velocity_demand == 0; }, 1000), 0);
  h.run(100);
  EXPECT_TRUE(h.bit(sw::kSpeedZero));
  EXPECT_TRUE(h.bit(sw::kTargetReached));
}

TEST(ProfileVelocity, MaxProfileVelocityLimitsTheTarget) {
  Harness h;
  h.in.max_profile_velocity = 50000;
  h.enable(OperationMode::ProfileVelocity);
  h.in.target_velocity = 200000;
  h.run(500);
  EXPECT_EQ(h.out.velocity_demand, 50000);
  EXPECT_NEAR(h.out.velocity_actual, 50000, 100);
}

TEST(ProfileTorque, RampsWithTorqueSlopeAndHolds) {
  Harness h;
  h.in.torque_slope = 10000;  // per mille per second: 500 per mille in 50 ms
  h.enable(OperationMode::ProfileTorque);
  h.drive.set_external_torque(0.635 + 0.02);  // balances 500 per mille and the friction
  h.in.target_torque = 500;
  h.run(25);
  EXPECT_NEAR(h.out.torque_demand, 250, 1);
  h.run(25);
  EXPECT_EQ(h.out.torque_demand, 500);
  h.run(10);
  EXPECT_NEAR(h.out.torque_actual, 500, 2);
  EXPECT_TRUE(h.bit(sw::kTargetReached));
  h.run(200);
  EXPECT_NEAR(h.out.torque_actual, 500, 2);
}

TEST(ProfileTorque, SpeedIsLimitedByMaxMotorSpeed) {
  Harness h;
  h.in.max_motor_speed = 1000;  // rpm
  h.in.torque_slope = 100000;
  h.enable(OperationMode::ProfileTorque);
  h.in.target_torque = 300;
  h.run(300);  // about 5 revolutions: still short of the limit switch
  const double rpm = h.out.velocity_actual * 60.0 / 131072.0;
  EXPECT_NEAR(rpm, 1000, 10);
  EXPECT_LT(h.out.torque_actual, 100);  // the limiter took the torque back
}

TEST(CyclicSyncPosition, FollowsTheMasterWithTheLoopLag) {
  Harness h;
  h.enable(OperationMode::CyclicSyncPosition);
  EXPECT_TRUE(h.bit(sw::kFollowsCommand));
  // Master ramp: 100 increments per 1 ms cycle = 100000 increments/s.
  std::int32_t target = 0;
  for (int i = 0; i < 500; ++i) {
    target += 100;
    h.in.target_position = target;
    h.step();
  }
  EXPECT_EQ(h.out.position_demand, target);
  // Type-1 position loop without feed-forward: lag = v / Kp = 100000/100.
  EXPECT_NEAR(h.out.following_error, 1000, 20);
  EXPECT_NEAR(h.out.velocity_actual, 100000, 200);
  h.run(200);  // master holds: the lag closes
  EXPECT_NEAR(h.out.position_actual, target, 3);
  EXPECT_TRUE(h.bit(sw::kTargetReached));
}

TEST(CyclicSyncPosition, OffsetsAndVelocityFeedForward) {
  Harness h;
  h.enable(OperationMode::CyclicSyncPosition);
  h.in.position_offset = 500;
  std::int32_t target = 0;
  for (int i = 0; i < 500; ++i) {
    target += 100;
    h.in.target_position = target;
    h.in.velocity_offset = 100000;  // full feed-forward of the ramp speed
    h.step();
  }
  EXPECT_EQ(h.out.position_demand, target + 500);
  EXPECT_NEAR(h.out.following_error, 0, 20);
}

TEST(CyclicSyncVelocity, TracksTheSetPoint) {
  Harness h;
  h.enable(OperationMode::CyclicSyncVelocity);
  h.in.target_velocity = 150000;
  h.in.velocity_offset = 10000;
  h.run(100);
  EXPECT_NEAR(h.out.velocity_actual, 160000, 300);
  EXPECT_TRUE(h.bit(sw::kFollowsCommand));
  h.in.target_velocity = -50000;
  h.in.velocity_offset = 0;
  h.run(100);
  EXPECT_NEAR(h.out.velocity_actual, -50000, 300);
}

TEST(CyclicSyncTorque, TorqueFollowsWithTheCurrentLoopLag) {
  Harness h;
  h.enable(OperationMode::CyclicSyncTorque);
  h.drive.set_external_torque(0.254 + 0.02 + 0.127);  // hold the rotor
  h.in.target_torque = 200;
  h.in.torque_offset = 100;
  h.step();
  // First-order lag, tau = 0.2 ms: after 1 ms 1 - e^-5 of the step.
  EXPECT_NEAR(h.out.torque_actual, 300 * (1 - 0.0067), 2);
  h.run(10);
  EXPECT_NEAR(h.out.torque_actual, 300, 1);
  EXPECT_TRUE(h.bit(sw::kTargetReached));
}

TEST(InterpolatedPosition, LinearBetweenPointsOverThePeriod) {
  Harness h;
  h.in.ip_period_value = 4;  // 4 ms: four drive cycles per point
  h.in.ip_period_index = -3;
  h.enable(OperationMode::InterpolatedPosition);
  EXPECT_FALSE(h.bit(sw::kIpModeActive));
  h.in.ip_position = 4000;
  h.command(kEnableOp | cw::kEnableIpMode);
  EXPECT_TRUE(h.bit(sw::kIpModeActive));
  EXPECT_EQ(h.out.position_demand, 1000);
  h.step();
  EXPECT_EQ(h.out.position_demand, 2000);
  h.in.ip_position = 8000;  // not taken before the period ends
  h.step();
  EXPECT_EQ(h.out.position_demand, 3000);
  h.step();
  EXPECT_EQ(h.out.position_demand, 4000);
  h.step();
  EXPECT_EQ(h.out.position_demand, 5000);
  h.run(3);
  EXPECT_EQ(h.out.position_demand, 8000);
  h.run(300);
  EXPECT_TRUE(h.bit(sw::kTargetReached));
  EXPECT_NEAR(h.out.position_actual, 8000, 5);
  // Bit 4 off: interpolation stops, the axis holds.
  h.in.ip_position = 20000;
  h.command(kEnableOp);
  EXPECT_FALSE(h.bit(sw::kIpModeActive));
  h.run(50);
  EXPECT_EQ(h.out.position_demand, 8000);
}

TEST(TorqueLimits, MaxTorqueAndDirectionalLimitsClamp) {
  Harness h;
  h.in.max_torque = 800;
  h.in.positive_torque_limit = 600;
  h.in.negative_torque_limit = 1000;
  h.enable(OperationMode::CyclicSyncTorque);
  h.drive.set_external_torque(10.0);  // stalls: nothing moves far
  h.in.target_torque = 2000;
  h.run(5);
  EXPECT_NEAR(h.out.torque_actual, 600, 2);
  EXPECT_TRUE(h.bit(sw::kInternalLimitActive));
  h.drive.set_external_torque(-10.0);
  h.in.target_torque = -2000;
  h.run(5);
  EXPECT_NEAR(h.out.torque_actual, -800, 2);
}

TEST(ModeSwitch, ChangesInOperationEnabledAndRejectsUnsupported) {
  Harness h;
  h.enable(OperationMode::CyclicSyncVelocity);
  h.in.target_velocity = 100000;
  h.run(100);
  h.in.modes_of_operation = static_cast<std::int8_t>(OperationMode::ProfilePosition);
  h.in.target_position = 0;
  h.step();
  EXPECT_EQ(h.out.modes_of_operation_display, 1);
  // PP without a set-point: the axis stops (generator holds, loop brakes).
  h.run(500);
  EXPECT_NEAR(h.out.velocity_actual, 0, 50);
  // VL is not in the generic drive's 6502h: ignored, warning set.
  h.in.modes_of_operation = static_cast<std::int8_t>(OperationMode::Velocity);
  h.step();
  EXPECT_EQ(h.out.modes_of_operation_display, 1);
  EXPECT_TRUE(h.bit(sw::kWarning));
  EXPECT_EQ(h.out.supported_drive_modes, 0x3EDu);
}

}  // namespace
}  // namespace ecat::ds402::test
