// Homing: every CiA 402 method 1-14, 17-30, 33, 34, 35, 37 ends on the
// position its definition names, with homing attained; the home position
// then reads as the home offset.
#include <gtest/gtest.h>

#include <cmath>

#include "ds402/controlword.hpp"
#include "ds402/statusword.hpp"
#include "harness.hpp"

namespace ecat::ds402::test {
namespace {

constexpr std::uint16_t kEnableOp = 0x000F;
constexpr double kRes = 131072;
constexpr double kIndexOffset = 1000;
double index_k(int k) { return k * kRes + kIndexOffset; }

enum class Layout { Window, PositiveSwitch, NegativeSwitch };

PlantParameters plant_for(Layout layout, double start) {
  PlantParameters p;
  p.index_offset = kIndexOffset;
  p.negative_limit_switch = -2.0e6;
  p.positive_limit_switch = 2.0e6;
  p.initial_position = start;
  switch (layout) {
    case Layout::Window: p.home_switch_low = 300000, p.home_switch_high = 500000; break;
    case Layout::PositiveSwitch: p.home_switch_low = 300000, p.home_switch_high = 3.0e6; break;
    case Layout::NegativeSwitch: p.home_switch_low = -3.0e6, p.home_switch_high = 300000; break;
  }
  return p;
}

struct Case {
  std::int8_t method;
  Layout layout;
  double start;
  double home;  // physical position of the home point
};

void PrintTo(const Case& c, std::ostream* os) { *os << "method " << int{c.method} << " from " << c.start; }

class HomingMethods : public ::testing::TestWithParam<Case> {};

TEST_P(HomingMethods, EndsOnTheDefinedPosition) {
  const Case c = GetParam();
  Harness h(generic_drive(), plant_for(c.layout, c.start));
  h.in.homing_method = c.method;
  h.in.homing_speed_switch = 500000;
  h.in.homing_speed_zero = 20000;
  h.in.homing_acceleration = 5000000;
  h.in.home_offset = 1234;
  h.enable(OperationMode::Homing);
  EXPECT_TRUE(h.bit(sw::kTargetReached));  // not started
  h.command(kEnableOp | cw::kHomingStart);
  const bool immediate = c.method == 35 || c.method == 37;  // no motion: done in the first cycle
  EXPECT_EQ(h.bit(sw::kTargetReached), immediate);
  EXPECT_EQ(h.bit(sw::kHomingAttained), immediate);
  const int cycles =
      immediate ? 1 : h.run_until([&] { return h.bit(sw::kHomingAttained) || h.bit(sw::kHomingError); }, 200000);
  ASSERT_GT(cycles, 0) << "homing did not end";
  ASSERT_FALSE(h.bit(sw::kHomingError));
  EXPECT_TRUE(h.bit(sw::kTargetReached));
  EXPECT_EQ(h.drive.homing_status(), HomingStatus::Attained);
  EXPECT_DOUBLE_EQ(h.drive.home_shift(), 1234 - c.home);
  h.run(50);  // the position loop settles on the home point
  EXPECT_NEAR(h.drive.plant().position(), c.home, 5);
  EXPECT_NEAR(h.out.position_actual, 1234, 5);
  EXPECT_TRUE(h.bit(sw::kHomingAttained));
}

// Home points: limit switches at +-2e6, index pulses at k*131072 + 1000,
// home switch [300000, 500000] (window) or a step at 300000.
INSTANTIATE_TEST_SUITE_P(
    Cia402, HomingMethods,
    ::testing::Values(
        Case{1, Layout::Window, 0, index_k(-15)}, Case{2, Layout::Window, 0, index_k(15)},
        Case{3, Layout::PositiveSwitch, 0, index_k(2)}, Case{3, Layout::PositiveSwitch, 1.0e6, index_k(2)},
        Case{4, Layout::PositiveSwitch, 0, index_k(3)}, Case{4, Layout::PositiveSwitch, 1.0e6, index_k(3)},
        Case{5, Layout::NegativeSwitch, 0, index_k(3)}, Case{5, Layout::NegativeSwitch, 1.0e6, index_k(3)},
        Case{6, Layout::NegativeSwitch, 0, index_k(2)}, Case{6, Layout::NegativeSwitch, 1.0e6, index_k(2)},
        Case{7, Layout::Window, 0, index_k(2)}, Case{7, Layout::Window, 1.0e6, index_k(2)},
        Case{7, Layout::Window, 400000, index_k(2)}, Case{8, Layout::Window, 0, index_k(3)},
        Case{8, Layout::Window, 400000, index_k(3)}, Case{9, Layout::Window, 0, index_k(3)},
        Case{9, Layout::Window, 1.0e6, index_k(3)}, Case{10, Layout::Window, 0, index_k(4)},
        Case{10, Layout::Window, 1.0e6, index_k(4)}, Case{11, Layout::Window, 1.0e6, index_k(4)},
        Case{11, Layout::Window, 0, index_k(4)}, Case{12, Layout::Window, 1.0e6, index_k(3)},
        Case{12, Layout::Window, 400000, index_k(3)}, Case{13, Layout::Window, 1.0e6, index_k(3)},
        Case{13, Layout::Window, 0, index_k(3)}, Case{14, Layout::Window, 1.0e6, index_k(2)},
        Case{14, Layout::Window, 0, index_k(2)}, Case{17, Layout::Window, 0, -2.0e6},
        Case{18, Layout::Window, 0, 2.0e6}, Case{19, Layout::PositiveSwitch, 0, 300000},
        Case{20, Layout::PositiveSwitch, 1.0e6, 300000}, Case{21, Layout::NegativeSwitch, 0, 300000},
        Case{22, Layout::NegativeSwitch, 1.0e6, 300000}, Case{23, Layout::Window, 1.0e6, 300000},
        Case{24, Layout::Window, 0, 300000}, Case{25, Layout::Window, 0, 500000},
        Case{26, Layout::Window, 400000, 500000}, Case{27, Layout::Window, 0, 500000},
        Case{28, Layout::Window, 1.0e6, 500000}, Case{29, Layout::Window, 1.0e6, 300000},
        Case{30, Layout::Window, 400000, 300000}, Case{33, Layout::Window, 0, index_k(-1)},
        Case{34, Layout::Window, 0, index_k(0)}, Case{34, Layout::Window, 1000, index_k(1)},
        Case{35, Layout::Window, 77777, 77777}, Case{37, Layout::Window, -5555, -5555}));

TEST(Homing, UnsupportedMethodIsAHomingError) {
  Harness h(*drive_personality("simtach-rse"));  // no index-pulse methods
  h.in.homing_method = 1;
  h.enable(OperationMode::Homing);
  h.command(kEnableOp | cw::kHomingStart);
  h.step();
  EXPECT_TRUE(h.bit(sw::kHomingError));
  EXPECT_TRUE(h.bit(sw::kTargetReached));  // velocity 0
  EXPECT_FALSE(h.bit(sw::kHomingAttained));
}

TEST(Homing, SimtachReportsHomeFoundInBit15) {
  Harness h(*drive_personality("simtach-rse"));
  h.in.homing_method = 35;
  h.enable(OperationMode::Homing);
  EXPECT_FALSE(h.bit(0x8000));
  h.command(kEnableOp | cw::kHomingStart);
  EXPECT_TRUE(h.bit(sw::kHomingAttained));
  h.in.modes_of_operation = 8;
  h.command(kEnableOp);
  EXPECT_TRUE(h.bit(0x8000));  // stays after leaving homing mode
  Harness generic;
  generic.in.homing_method = 35;
  generic.enable(OperationMode::Homing);
  generic.command(kEnableOp | cw::kHomingStart);
  EXPECT_FALSE(generic.bit(0x8000));
}

TEST(Homing, MissingSwitchEndsInErrorAtTheLimit) {
  PlantParameters p = plant_for(Layout::Window, 0);
  p.home_switch_low = 3.0e6;  // beyond the positive limit switch: never found
  p.home_switch_high = 3.1e6;
  Harness h(generic_drive(), p);
  h.in.homing_method = 3;
  h.in.homing_speed_switch = 500000;
  h.in.homing_acceleration = 5000000;
  h.enable(OperationMode::Homing);
  h.command(kEnableOp | cw::kHomingStart);
  ASSERT_GT(h.run_until([&] { return h.bit(sw::kHomingError); }, 20000), 0);
  EXPECT_FALSE(h.bit(sw::kTargetReached));  // still braking
  ASSERT_GT(h.run_until([&] { return h.bit(sw::kTargetReached); }, 2000), 0);
  EXPECT_TRUE(h.bit(sw::kHomingError));
  EXPECT_EQ(h.drive.state(), PdsState::OperationEnabled);  // the limit is no fault while homing
}

TEST(Homing, ClearingTheStartBitInterrupts) {
  Harness h;
  h.in.homing_method = 1;
  h.in.homing_speed_switch = 100000;
  h.enable(OperationMode::Homing);
  h.command(kEnableOp | cw::kHomingStart);
  h.run(100);
  EXPECT_FALSE(h.bit(sw::kTargetReached));  // in progress: 0 0 0
  h.command(kEnableOp);
  ASSERT_GT(h.run_until([&] { return h.bit(sw::kTargetReached); }, 2000), 0);  // interrupted: 0 0 1
  EXPECT_FALSE(h.bit(sw::kHomingAttained));
  EXPECT_FALSE(h.bit(sw::kHomingError));
  EXPECT_EQ(h.drive.homing_status(), HomingStatus::NotStarted);
}

TEST(Homing, HomedCoordinatesCarryIntoProfilePosition) {
  Harness h(generic_drive(), plant_for(Layout::Window, 0));
  h.in.homing_method = 24;  // home = 300000 physical
  h.in.homing_speed_switch = 500000;
  h.in.homing_speed_zero = 20000;
  h.in.homing_acceleration = 5000000;
  h.in.home_offset = 0;
  h.enable(OperationMode::Homing);
  h.command(kEnableOp | cw::kHomingStart);
  ASSERT_GT(h.run_until([&] { return h.bit(sw::kHomingAttained); }, 100000), 0);
  h.in.modes_of_operation = 1;
  h.command(kEnableOp);
  h.in.target_position = 100000;
  h.command(kEnableOp | cw::kNewSetPoint);
  h.command(kEnableOp);
  ASSERT_GT(h.run_until([&] { return h.bit(sw::kTargetReached); }, 10000), 0);
  EXPECT_NEAR(h.drive.plant().position(), 400000, 100);
  EXPECT_NEAR(h.out.position_actual, 100000, 100);
  EXPECT_EQ(h.out.digital_inputs & 0x4u, 0x4u);  // on the home switch
}

}  // namespace
}  // namespace ecat::ds402::test
