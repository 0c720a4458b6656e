// Welcon manufacturer homing methods -3/-4 ("current threshold", seed 000
// §5.4.3.33/34): move at 6099h:01 until the motor current exceeds 2402h,
// i.e. the axis presses on a mechanical stop; that stop is home and reads
// the home offset 607Ch.
#include <gtest/gtest.h>

#include "ds402/controlword.hpp"
#include "ds402/homing.hpp"
#include "ds402/statusword.hpp"
#include "harness.hpp"

namespace ecat::ds402::test {
namespace {

constexpr std::uint16_t kEnableOp = 0x000F;
constexpr double kPositiveStop = 250000;   // increments
constexpr double kNegativeStop = -180000;

PlantParameters with_stops(double start = 0) {
  PlantParameters p;
  p.negative_limit_switch = -2.0e6;
  p.positive_limit_switch = 2.0e6;
  p.negative_hard_stop = kNegativeStop;
  p.positive_hard_stop = kPositiveStop;
  p.initial_position = start;
  return p;
}

void start_homing(Harness& h, std::int8_t method, std::uint32_t threshold_ma) {
  h.in.homing_method = method;
  h.in.homing_speed_switch = 200000;
  h.in.homing_speed_zero = 20000;
  h.in.homing_acceleration = 2000000;
  h.in.home_offset = 777;
  h.in.homing_current_threshold = threshold_ma;
  h.enable(OperationMode::Homing);
  h.command(kEnableOp | cw::kHomingStart);
}

TEST(HomingCurrentThreshold, MethodsAreDefinedAndOfferedByTheWelconOnly) {
  ASSERT_TRUE(homing_method(-3).has_value());
  EXPECT_EQ(homing_method(-3)->kind, HomingMethod::Kind::CurrentThreshold);
  EXPECT_EQ(homing_method(-3)->final_direction, 1);
  EXPECT_EQ(homing_method(-4)->final_direction, -1);
  for (int m : {-1, -2, -5, -128}) EXPECT_FALSE(homing_method(static_cast<std::int8_t>(m)).has_value()) << m;
  const DriveConfig welcon = *drive_personality("welcon");
  EXPECT_TRUE(welcon.supports_homing(-3));
  EXPECT_TRUE(welcon.supports_homing(-4));
  EXPECT_EQ(welcon.homing_current_threshold_index, 0x2402);
  EXPECT_FALSE(generic_drive().supports_homing(-3));
  EXPECT_FALSE(drive_personality("leadshine-isv2-can")->supports_homing(-3));
}

TEST(HomingCurrentThreshold, PositiveStopBecomesHome) {
  Harness h(*drive_personality("welcon"), with_stops(10000));
  start_homing(h, -3, 300);  // 300 mA = 0.135 N·m: above the running current, below the torque limit
  EXPECT_FALSE(h.bit(sw::kHomingAttained));
  // Running at 6099h:01 the current stays below the threshold.
  h.run(200);
  EXPECT_FALSE(h.bit(sw::kHomingAttained));
  EXPECT_NEAR(h.out.velocity_actual, 200000, 2000);
  EXPECT_LT(h.drive.plant().torque() / h.drive.plant().parameters().torque_constant * 1000, 300);
  // The stop is 240000 increments away: 0.1 s accelerating (10000), then
  // 1.15 s at speed, less the 200 cycles run, plus the position loop's lag.
  const int impact = h.run_until([&] { return h.drive.plant().at_hard_stop(); }, 3000);
  EXPECT_GT(impact, 1000);
  EXPECT_LT(impact, 1100);
  EXPECT_FALSE(h.bit(sw::kHomingAttained));
  // The current rises above the threshold within a few cycles of the
  // impact; the reference then returns to the stop at 6099h:02.
  const int cycles = h.run_until([&] { return h.bit(sw::kHomingAttained); }, 3000);
  ASSERT_GT(cycles, 0);
  EXPECT_LT(cycles, 200);
  EXPECT_FALSE(h.bit(sw::kHomingError));
  EXPECT_TRUE(h.bit(sw::kTargetReached));
  EXPECT_TRUE(h.drive.plant().at_hard_stop());
  EXPECT_EQ(h.drive.plant().position(), kPositiveStop);
  EXPECT_EQ(h.out.position_actual, 777);  // the stop reads 607Ch
  EXPECT_EQ(h.drive.home_shift(), 777 - kPositiveStop);
}

TEST(HomingCurrentThreshold, NegativeStopBecomesHome) {
  Harness h(*drive_personality("welcon"), with_stops(0));
  start_homing(h, -4, 300);
  ASSERT_GT(h.run_until([&] { return h.bit(sw::kHomingAttained); }, 3000), 0);
  EXPECT_EQ(h.drive.plant().position(), kNegativeStop);
  EXPECT_EQ(h.out.position_actual, 777);
  // PP to 0 in the homed coordinates: 777 increments off the stop.
  h.in.modes_of_operation = 1;
  h.in.target_position = 777 + 50000;
  h.in.profile_velocity = 100000;
  h.command(kEnableOp);
  h.command(kEnableOp | cw::kNewSetPoint);
  EXPECT_TRUE(h.bit(sw::kSetPointAcknowledge));
  h.command(kEnableOp);
  ASSERT_GT(h.run_until([&] { return h.bit(sw::kTargetReached); }, 3000), 0);
  EXPECT_NEAR(h.drive.plant().position(), kNegativeStop + 50000, 100);
}

TEST(HomingCurrentThreshold, NoStopBeforeTheLimitSwitchIsAHomingError) {
  PlantParameters p = with_stops(0);
  p.positive_hard_stop = PlantParameters::kUnset;  // nothing to press on
  p.positive_limit_switch = 150000;
  Harness h(*drive_personality("welcon"), p);
  start_homing(h, -3, 300);
  ASSERT_GT(h.run_until([&] { return h.bit(sw::kHomingError); }, 3000), 0);
  EXPECT_FALSE(h.bit(sw::kHomingAttained));
  EXPECT_GE(h.drive.plant().position(), 150000);
}

TEST(HomingCurrentThreshold, ThresholdAboveTheRunningCurrentOnly) {
  // A threshold below the current needed to run trips at once: the stop is
  // "found" where the axis starts (as on the real drive).
  Harness h(*drive_personality("welcon"), with_stops(5000));
  start_homing(h, -3, 1);
  ASSERT_GT(h.run_until([&] { return h.bit(sw::kHomingAttained); }, 3000), 0);
  EXPECT_LT(h.drive.plant().position(), 6000);
  EXPECT_NEAR(h.out.position_actual, 777, 20);
  EXPECT_FALSE(h.drive.plant().at_hard_stop());
}

TEST(HomingCurrentThreshold, PlantEndStopsClampAndAreChecked) {
  const std::pair<std::string, double> bad[] = {{"negative_hard_stop", 10}, {"positive_hard_stop", 5}};
  EXPECT_FALSE(plant_parameters_from(bad).has_value());
  const std::pair<std::string, double> good[] = {{"negative_hard_stop", -10}, {"positive_hard_stop", 5}};
  const auto p = plant_parameters_from(good);
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->positive_hard_stop, 5);
}

}  // namespace
}  // namespace ecat::ds402::test
