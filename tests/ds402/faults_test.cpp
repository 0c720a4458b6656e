// Faults: each raises 603Fh, 1001h and an EMCY request, runs the 605Eh
// reaction through Fault reaction active into Fault, and clears on the
// rising edge of controlword bit 7. Quick stop with 605Ah.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "ds402/controlword.hpp"
#include "ds402/statusword.hpp"
#include "harness.hpp"

namespace ecat::ds402::test {
namespace {

constexpr std::uint16_t kEnableOp = 0x000F;

void expect_emcy(Harness& h, std::uint16_t code, std::uint8_t reg) {
  auto r = h.drive.emergencies().pop();
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->error_code, code);
  EXPECT_EQ(r->error_register, reg);
}

// Runs into Fault, resets, and checks the reset EMCY and Switch on disabled.
void expect_fault_then_reset(Harness& h, std::uint16_t code, std::uint8_t reg) {
  ASSERT_GT(h.run_until([&] { return h.drive.state() == PdsState::Fault; }, 5000), 0);
  EXPECT_EQ(h.out.error_code, code);
  EXPECT_EQ(h.out.error_register, reg);
  EXPECT_EQ(h.out.statusword & sw::kStateMaskNoQs, sw::kFaultState);
  expect_emcy(h, code, reg);
  h.in.sync_lost = false;
  h.command(0x0000);
  h.command(cw::kFaultReset);
  EXPECT_EQ(h.drive.state(), PdsState::SwitchOnDisabled);
  EXPECT_EQ(h.out.error_code, 0);
  EXPECT_EQ(h.out.error_register, 0);
  expect_emcy(h, kEmcyErrorReset, 0);
}

TEST(Faults, FollowingErrorWithQuickStopReaction) {
  Harness h;
  h.in.following_error_window = 5000;
  h.in.following_error_timeout = 10;
  h.in.fault_reaction_option = 2;
  h.in.quick_stop_deceleration = 10000000;
  h.enable(OperationMode::CyclicSyncPosition);
  h.in.target_position = 20000;  // a step far beyond the window
  int cycles = 0;
  h.run_until(
      [&] {
        ++cycles;
        return h.drive.state() == PdsState::FaultReactionActive;
      },
      100);
  EXPECT_GE(cycles, 11);  // longer than 6066h = 10 ms
  EXPECT_LE(cycles, 14);
  EXPECT_TRUE(h.bit(sw::kFault));
  EXPECT_EQ(h.out.statusword & sw::kStateMaskNoQs, sw::kFaultReactionActiveState);
  expect_fault_then_reset(h, 0x8611, 0x21);
}

TEST(Faults, OverSpeed) {
  Harness h;
  h.in.max_motor_speed = 8000;
  h.enable(OperationMode::CyclicSyncVelocity);
  h.in.target_velocity = static_cast<std::int32_t>(7000.0 * 131072 / 60);
  expect_fault_then_reset(h, 0x8400, 0x21);
}

TEST(Faults, OverTorqueWhenStalled) {
  PlantParameters p;
  p.over_torque_time = 0.2;
  Harness h(generic_drive(), p);
  h.enable(OperationMode::CyclicSyncVelocity);
  h.drive.set_external_torque(3.9);  // just above the peak torque
  h.in.target_velocity = 100000;
  const int cycles = h.run_until([&] { return h.out.error_code != 0; }, 1000);
  EXPECT_NEAR(cycles, 200, 5);
  h.drive.set_external_torque(0);
  expect_fault_then_reset(h, 0x8311, 0x03);
}

TEST(Faults, SoftwareLimitInVelocityMode) {
  Harness h;
  h.in.software_limit_min = -50000;
  h.in.software_limit_max = 50000;
  h.enable(OperationMode::CyclicSyncVelocity);
  h.in.target_velocity = 100000;
  ASSERT_GT(h.run_until([&] { return h.out.error_code != 0; }, 2000), 0);
  EXPECT_NEAR(h.out.position_actual, 50000, 300);
  expect_fault_then_reset(h, 0x8612, 0x21);
}

TEST(Faults, HardwareLimitSwitchAndMovingAway) {
  PlantParameters p;
  p.initial_position = 1.9e6;
  p.positive_limit_switch = 2.0e6;
  Harness h(generic_drive(), p);
  h.enable(OperationMode::ProfileVelocity);
  h.in.target_velocity = 100000;
  ASSERT_GT(h.run_until([&] { return h.out.error_code != 0; }, 3000), 0);
  EXPECT_TRUE(h.out.digital_inputs & 0x2u);  // 60FDh bit 1: positive limit
  expect_fault_then_reset(h, 0xFF03, 0x81);
  EXPECT_EQ(h.out.velocity_actual, 0);  // the quick stop ended at rest
  // Away from the switch is allowed.
  h.in.target_velocity = -100000;
  h.enable(OperationMode::ProfileVelocity);
  h.run(500);
  EXPECT_EQ(h.drive.state(), PdsState::OperationEnabled);
  EXPECT_FALSE(h.out.digital_inputs & 0x2u);
}

TEST(Faults, LossOfSync) {
  Harness h;
  h.enable(OperationMode::CyclicSyncPosition);
  h.in.sync_lost = true;
  expect_fault_then_reset(h, 0x8700, 0x11);
}

TEST(Faults, ResetNeedsARisingEdgeAndNoFaultOutsideOperation) {
  Harness h;
  h.in.sync_lost = true;  // power stage off: not monitored
  h.run(10);
  EXPECT_EQ(h.drive.state(), PdsState::SwitchOnDisabled);
  h.in.sync_lost = false;
  h.enable(OperationMode::CyclicSyncPosition);
  h.drive.raise_fault(FaultKind::SyncLost);
  h.in.controlword = cw::kFaultReset;  // bit 7 already high while the fault comes
  h.run(5);
  EXPECT_EQ(h.drive.state(), PdsState::Fault);
  h.run(5);
  EXPECT_EQ(h.drive.state(), PdsState::Fault);  // no edge, no reset
  h.command(0);
  h.command(cw::kFaultReset);
  EXPECT_EQ(h.drive.state(), PdsState::SwitchOnDisabled);
}

// Time to stop from 200000 inc/s in PV under each fault reaction.
int reaction_cycles(std::int16_t option, DriveConfig config = generic_drive()) {
  Harness h(std::move(config));
  h.in.profile_deceleration = 1000000;    // 0.2 s from 200000
  h.in.quick_stop_deceleration = 4000000;  // 0.05 s
  h.in.fault_reaction_option = option;
  h.enable(OperationMode::ProfileVelocity);
  h.in.target_velocity = 200000;
  h.run(400);
  h.drive.raise_fault(FaultKind::SyncLost);
  h.step();
  EXPECT_EQ(h.drive.state(), PdsState::FaultReactionActive);
  return h.run_until([&] { return h.drive.state() == PdsState::Fault; }, 2000);
}

TEST(Faults, ReactionFollows605E) {
  EXPECT_EQ(reaction_cycles(0), 1);           // disable drive: at once
  // Ramp time, then the position loop settling the motor to rest (~5/Kp).
  const int slow = reaction_cycles(1);  // slow-down ramp 6084h: 0.2 s
  EXPECT_GE(slow, 200);
  EXPECT_LE(slow, 260);
  const int quick = reaction_cycles(2);  // quick stop ramp 6085h: 0.05 s
  EXPECT_GE(quick, 50);
  EXPECT_LE(quick, 110);
  EXPECT_LT(reaction_cycles(3), 20);          // torque limit
  // Welcon supports 605Eh = 0 only: a written 2 falls back to 0.
  EXPECT_EQ(reaction_cycles(2, *drive_personality("welcon")), 1);
}

TEST(Faults, YaskawaSendsFF00WithTheAlarmNumber) {
  Harness h(*drive_personality("yaskawa-sigma5-sd"));
  h.enable(OperationMode::CyclicSyncPosition);
  h.drive.raise_fault(FaultKind::OverSpeed);
  auto r = h.drive.emergencies().pop();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->error_code, 0xFF00);
  EXPECT_EQ(r->manufacturer[1], 0x10);
  EXPECT_EQ(r->manufacturer[2], 0x05);
  h.step();
  EXPECT_EQ(h.out.error_code, 0x0510);
}

TEST(QuickStop, RampThenSwitchOnDisabled) {
  Harness h;
  h.in.quick_stop_deceleration = 2000000;
  h.in.quick_stop_option = 2;
  h.enable(OperationMode::ProfileVelocity);
  h.in.target_velocity = 200000;
  h.run(400);
  h.command(0x000B);  // quick stop: bit 2 low
  EXPECT_EQ(h.drive.state(), PdsState::QuickStopActive);
  EXPECT_EQ(h.out.statusword & sw::kStateMask, sw::kQuickStopActiveState);
  const int ramp = h.run_until([&] { return h.out.velocity_demand == 0; }, 1000);
  EXPECT_NEAR(ramp, 100, 2);  // 200000 / 2e6 = 0.1 s
  EXPECT_EQ(h.drive.state(), PdsState::QuickStopActive);
  const int settle = h.run_until([&] { return h.drive.state() == PdsState::SwitchOnDisabled; }, 1000);
  EXPECT_GT(settle, 0);
  EXPECT_LT(settle, 60);
  EXPECT_EQ(h.drive.last_transition(), 12);
}

TEST(QuickStop, StayOption6AndBackToOperation) {
  Harness h;
  h.in.quick_stop_option = 6;
  h.enable(OperationMode::ProfileVelocity);
  h.in.target_velocity = 100000;
  h.run(300);
  h.command(0x000B);
  h.run(200);
  EXPECT_EQ(h.drive.state(), PdsState::QuickStopActive);
  EXPECT_TRUE(h.bit(sw::kTargetReached));
  EXPECT_NEAR(h.out.velocity_actual, 0, 100);
  h.command(kEnableOp);
  EXPECT_EQ(h.drive.state(), PdsState::OperationEnabled);
  EXPECT_EQ(h.drive.last_transition(), 16);
}

TEST(DisableOperation, SlowDownRampBeforeSwitchedOn) {
  Harness h;
  h.in.disable_operation_option = 1;
  h.in.profile_deceleration = 1000000;
  h.enable(OperationMode::ProfileVelocity);
  h.in.target_velocity = 100000;
  h.run(300);
  h.command(0x0007);
  EXPECT_EQ(h.drive.state(), PdsState::OperationEnabled);  // ramping
  const int cycles = h.run_until([&] { return h.drive.state() == PdsState::SwitchedOn; }, 1000);
  EXPECT_GE(cycles, 100);  // 100000 / 1e6 = 0.1 s, then settling
  EXPECT_LE(cycles, 160);
  EXPECT_EQ(h.drive.last_transition(), 5);
}

}  // namespace
}  // namespace ecat::ds402::test
