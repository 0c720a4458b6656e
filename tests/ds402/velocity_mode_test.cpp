// Velocity mode vl (CiA 402-2 vl objects 6042h-6051h): the set-point chain,
// the ramps (exact slopes per 1 ms cycle), the limit function, the vl
// controlword bits, halt and quick stop on the vl ramps.
#include <gtest/gtest.h>

#include "ds402/controlword.hpp"
#include "ds402/statusword.hpp"
#include "ds402/velocity_mode.hpp"
#include "harness.hpp"

namespace ecat::ds402::test {
namespace {

// Enable operation with the three vl ramp bits (enable, unlock, reference).
constexpr std::uint16_t kVlRun = 0x000F | cw_vl::kEnableRamp | cw_vl::kUnlockRamp | cw_vl::kReferenceRamp;
constexpr double kIncPerRpm = 131072.0 / 60.0;  // the default plant's encoder

Harness welcon(std::int32_t dimension_numerator = 1, std::int32_t dimension_denominator = 1) {
  Harness h(*drive_personality("welcon"));
  h.in.vl_dimension_numerator = dimension_numerator;
  h.in.vl_dimension_denominator = dimension_denominator;
  h.in.vl_acceleration_delta_speed = 1000;  // 1000 rpm/s: 1 rpm per cycle
  h.in.vl_acceleration_delta_time = 1;
  h.in.vl_deceleration_delta_speed = 4000;  // 2 s: 2 rpm per cycle
  h.in.vl_deceleration_delta_time = 2;
  h.in.vl_quick_stop_delta_speed = 3000;  // 3 rpm per cycle
  h.in.vl_quick_stop_delta_time = 1;
  h.in.vl_max_amount = 3000;
  h.enable(OperationMode::Velocity);
  h.command(kVlRun);
  return h;
}

TEST(VelocityModeVl, RampsUpAndDownAtTheExactSlopes) {
  Harness h = welcon();
  EXPECT_EQ(h.out.modes_of_operation_display, 2);
  EXPECT_TRUE(h.bit(sw::kTargetReached));  // target 0, ramp at 0
  h.in.vl_target_velocity = 300;
  h.run(100);
  EXPECT_EQ(h.out.vl_velocity_demand, 100);
  EXPECT_FALSE(h.bit(sw::kTargetReached));
  EXPECT_EQ(h.out.velocity_demand, 218453);  // 100 rpm in increments/s (606Bh)
  h.run(199);
  EXPECT_EQ(h.out.vl_velocity_demand, 299);
  EXPECT_FALSE(h.bit(sw::kTargetReached));
  h.step();
  EXPECT_EQ(h.out.vl_velocity_demand, 300);
  EXPECT_TRUE(h.bit(sw::kTargetReached));
  h.run(300);
  EXPECT_EQ(h.out.vl_velocity_actual, 300);
  EXPECT_NEAR(h.out.velocity_actual, 300 * kIncPerRpm, 50);
  // Down at 6049h: 2 rpm per cycle.
  h.in.vl_target_velocity = 100;
  h.run(50);
  EXPECT_EQ(h.out.vl_velocity_demand, 200);
  h.run(50);
  EXPECT_EQ(h.out.vl_velocity_demand, 100);
  EXPECT_TRUE(h.bit(sw::kTargetReached));
  // Reversing: down to 0 at 6049h (50 cycles), then up at 6048h.
  h.in.vl_target_velocity = -100;
  h.run(50);
  EXPECT_EQ(h.out.vl_velocity_demand, 0);
  h.run(60);
  EXPECT_EQ(h.out.vl_velocity_demand, -60);
  h.run(40);
  EXPECT_EQ(h.out.vl_velocity_demand, -100);
  h.run(300);
  EXPECT_EQ(h.out.vl_velocity_actual, -100);
}

TEST(VelocityModeVl, ZeroCrossingWithinACycleKeepsTheRestOfTheCycle) {
  Harness h = welcon();
  h.in.vl_deceleration_delta_speed = 1500;  // 1.5 rpm per cycle
  h.in.vl_deceleration_delta_time = 1;
  h.in.vl_target_velocity = 3;
  h.run(3);
  EXPECT_EQ(h.out.vl_velocity_demand, 3);
  h.in.vl_target_velocity = -10;
  h.run(2);  // 3 -> 1.5 -> 0 exactly
  EXPECT_EQ(h.out.vl_velocity_demand, 0);
  h.in.vl_deceleration_delta_speed = 2000;  // 2 rpm/cycle: from 0 no longer matters
  h.in.vl_target_velocity = 1;
  h.run(1);  // 0 -> 1 (acceleration 1 rpm per cycle)
  EXPECT_EQ(h.out.vl_velocity_demand, 1);
  h.in.vl_target_velocity = -10;
  h.step();  // 1 -> 0 takes half the cycle at 2 rpm/ms, the other half accelerates to -0.5
  EXPECT_NEAR(h.drive.velocity_demand(), -0.5 * kIncPerRpm, 1e-6);
}

TEST(VelocityModeVl, LimitFunctionAndInternalLimitBit) {
  Harness h = welcon();
  h.in.vl_max_amount = 200;
  h.in.vl_min_amount = 50;
  h.in.vl_target_velocity = 500;
  h.step();
  EXPECT_TRUE(h.bit(sw::kInternalLimitActive));
  h.run(300);
  EXPECT_EQ(h.out.vl_velocity_demand, 200);
  EXPECT_TRUE(h.bit(sw::kTargetReached));
  h.in.vl_target_velocity = 150;  // inside: no limit
  h.step();
  EXPECT_FALSE(h.bit(sw::kInternalLimitActive));
  h.in.vl_target_velocity = 10;  // below the min amount: raised to it
  h.run(100);
  EXPECT_TRUE(h.bit(sw::kInternalLimitActive));
  EXPECT_EQ(h.out.vl_velocity_demand, 50);
  h.in.vl_target_velocity = 0;  // 0 stays 0
  h.run(30);
  EXPECT_FALSE(h.bit(sw::kInternalLimitActive));
  EXPECT_EQ(h.out.vl_velocity_demand, 0);
  h.in.vl_target_velocity = -10;
  h.run(60);
  EXPECT_EQ(h.out.vl_velocity_demand, -50);
  bool limited = false;
  EXPECT_EQ(VelocityMode::limit(-900, h.in, limited), -200);
  EXPECT_TRUE(limited);
}

TEST(VelocityModeVl, SetPointAndDimensionFactors) {
  Harness h = welcon();
  // 604Bh 1/10: 6042h = 1000 asks for 100 vl units; 6043h/6044h are in 6042h's units.
  h.in.vl_setpoint_numerator = 1;
  h.in.vl_setpoint_denominator = 10;
  h.in.vl_target_velocity = 1000;
  h.run(50);
  EXPECT_EQ(h.out.vl_velocity_demand, 500);  // 50 rpm
  EXPECT_EQ(h.drive.velocity_demand(), 50 * kIncPerRpm);
  h.run(400);
  EXPECT_EQ(h.out.vl_velocity_demand, 1000);
  EXPECT_NEAR(h.out.velocity_actual, 100 * kIncPerRpm, 20);
}

TEST(VelocityModeVl, DimensionFactorSetsTheVlUnit) {
  // 604Ch 1/60: a vl unit is rev/s (the rpm value times 1/60). The ramp
  // slopes are in vl units too: 5 rev/s per 1 s.
  Harness h = welcon(1, 60);
  h.in.vl_target_velocity = 5;  // 300 rpm
  h.in.vl_acceleration_delta_speed = 5;
  h.in.vl_acceleration_delta_time = 1;
  h.step();
  EXPECT_NEAR(h.drive.velocity_demand(), 0.005 * 131072.0, 1e-6);  // 0.005 rev/s
  h.run(998);
  EXPECT_EQ(h.out.vl_velocity_demand, 5);  // 4.995 rounds to 5
  EXPECT_FALSE(h.bit(sw::kTargetReached));
  h.step();
  EXPECT_TRUE(h.bit(sw::kTargetReached));
  EXPECT_NEAR(h.drive.velocity_demand(), 5 * 131072.0, 1e-6);
  h.run(300);
  EXPECT_NEAR(h.out.velocity_actual, 300 * kIncPerRpm, 20);
  EXPECT_EQ(h.out.vl_velocity_actual, 5);
}

TEST(VelocityModeVl, ControlwordRampBits) {
  Harness h = welcon();
  h.in.vl_target_velocity = 200;
  h.run(100);
  ASSERT_EQ(h.out.vl_velocity_demand, 100);
  // Bit 5 = 0: the ramp output is held.
  h.in.controlword = kVlRun & ~cw_vl::kUnlockRamp;
  h.run(50);
  EXPECT_EQ(h.out.vl_velocity_demand, 100);
  EXPECT_FALSE(h.bit(sw::kTargetReached));
  // Bit 6 = 0: the ramp input is 0, the output ramps down at 6049h.
  h.in.controlword = kVlRun & ~cw_vl::kReferenceRamp;
  h.run(25);
  EXPECT_EQ(h.out.vl_velocity_demand, 50);
  h.in.controlword = kVlRun;
  h.run(50);
  EXPECT_EQ(h.out.vl_velocity_demand, 100);
  // Bit 4 = 0: the output is forced to 0 at once.
  h.in.controlword = kVlRun & ~cw_vl::kEnableRamp;
  h.step();
  EXPECT_EQ(h.out.vl_velocity_demand, 0);
  EXPECT_EQ(h.drive.state(), PdsState::OperationEnabled);
  h.run(500);
  EXPECT_EQ(h.out.vl_velocity_actual, 0);
}

TEST(VelocityModeVl, HaltUsesTheSlowDownOrQuickStopRamp) {
  Harness h = welcon();
  h.in.vl_target_velocity = 300;
  h.run(600);
  h.in.halt_option = 1;  // 6049h: 2 rpm per cycle
  h.command(kVlRun | cw::kHalt);
  EXPECT_EQ(h.out.vl_velocity_demand, 298);
  h.run(49);
  EXPECT_EQ(h.out.vl_velocity_demand, 200);
  EXPECT_FALSE(h.bit(sw::kTargetReached));
  h.run(100);
  EXPECT_EQ(h.out.vl_velocity_demand, 0);
  EXPECT_TRUE(h.bit(sw::kTargetReached));
  // Releasing halt ramps back up at 6048h.
  h.command(kVlRun);
  EXPECT_EQ(h.out.vl_velocity_demand, 1);
  h.run(299);
  EXPECT_EQ(h.out.vl_velocity_demand, 300);
  h.run(300);
  h.in.halt_option = 2;  // 604Ah: 3 rpm per cycle
  h.command(kVlRun | cw::kHalt);
  EXPECT_EQ(h.out.vl_velocity_demand, 297);
  h.run(99);
  EXPECT_EQ(h.out.vl_velocity_demand, 0);
}

TEST(VelocityModeVl, QuickStopRampsOn604Ah) {
  Harness h = welcon();
  h.in.vl_target_velocity = 300;
  h.run(600);
  h.in.quick_stop_option = 6;  // quick stop ramp, stay in Quick stop active
  h.command(0x0002 | cw_vl::kEnableRamp | cw_vl::kUnlockRamp | cw_vl::kReferenceRamp);
  EXPECT_EQ(h.drive.state(), PdsState::QuickStopActive);
  const int start = h.out.vl_velocity_demand;
  EXPECT_NEAR(start, 297, 1);  // from the motor's velocity, 3 rpm per cycle
  h.run(50);
  EXPECT_EQ(h.out.vl_velocity_demand, start - 150);
  const int cycles = h.run_until([&] { return h.bit(sw::kTargetReached); }, 500);
  EXPECT_GT(cycles, 40);
  EXPECT_LT(cycles, 200);
  EXPECT_EQ(h.out.vl_velocity_demand, 0);
  EXPECT_EQ(h.drive.state(), PdsState::QuickStopActive);
  // Quick stop option 1 uses the slow-down ramp (6049h, 2 rpm per cycle).
  h.command(kVlRun);  // transition 16
  h.run(600);
  ASSERT_EQ(h.out.vl_velocity_demand, 300);
  h.in.quick_stop_option = 1;
  h.command(0x0002 | (kVlRun & 0x70));
  const int from = h.out.vl_velocity_demand;
  h.run(50);
  EXPECT_EQ(h.out.vl_velocity_demand, from - 100);
  ASSERT_GT(h.run_until([&] { return h.drive.state() == PdsState::SwitchOnDisabled; }, 500), 0);
}

TEST(VelocityModeVl, RampTimesWhenTheDeltaObjectsAreZero) {
  Harness h = welcon();
  h.in.vl_acceleration_delta_speed = 0;  // 604Fh: 0 -> 604Eh in 1500 ms = 2 rpm per cycle
  h.in.vl_velocity_reference = 3000;
  h.in.vl_ramp_function_time = 1500;
  h.in.vl_deceleration_delta_time = 0;  // 6050h: 3000 ms = 1 rpm per cycle
  h.in.vl_slow_down_time = 3000;
  h.in.vl_target_velocity = 400;
  h.run(100);
  EXPECT_EQ(h.out.vl_velocity_demand, 200);
  h.run(200);
  h.in.vl_target_velocity = 0;
  h.run(100);
  EXPECT_EQ(h.out.vl_velocity_demand, 300);
  EXPECT_EQ(VelocityMode::acceleration(h.in), 2000.0);
  EXPECT_EQ(VelocityMode::deceleration(h.in), 1000.0);
  h.in.vl_velocity_reference = 0;  // neither set: no ramp
  EXPECT_EQ(VelocityMode::deceleration(h.in), 0.0);
  h.step();
  EXPECT_EQ(h.out.vl_velocity_demand, 0);
}

TEST(VelocityModeVl, RefusedWhereTheDriveDoesNotAdvertiseIt) {
  Harness h;  // generic: 6502h without vl
  h.enable(OperationMode::CyclicSyncPosition);
  h.in.modes_of_operation = 2;
  h.step();
  EXPECT_EQ(h.out.modes_of_operation_display, 8);
  EXPECT_TRUE(h.bit(sw::kWarning));
}

}  // namespace
}  // namespace ecat::ds402::test
