// PDS state machine: every transition of CiA 402-2 Figure 8 with the exact
// controlword patterns, forbidden commands ignored, statusword per state.
#include <gtest/gtest.h>

#include "ds402/state_machine.hpp"
#include "ds402/statusword.hpp"

namespace ecat::ds402 {
namespace {

constexpr std::uint16_t kShutdown = 0x0006;
constexpr std::uint16_t kSwitchOn = 0x0007;
constexpr std::uint16_t kEnableOp = 0x000F;
constexpr std::uint16_t kDisableVoltage = 0x0000;
constexpr std::uint16_t kQuickStop = 0x0002;
constexpr std::uint16_t kDisableOp = 0x0007;
constexpr std::uint16_t kFaultReset = 0x0080;

struct Sm {
  StateMachine sm;
  StateMachine::Inputs in;
  int cmd(std::uint16_t cw) {
    in.controlword = cw;
    return sm.step(in);
  }
  void to(PdsState target) {
    cmd(0);  // 1: -> Switch on disabled
    if (target == PdsState::SwitchOnDisabled) return;
    cmd(kShutdown);
    if (target == PdsState::ReadyToSwitchOn) return;
    cmd(kSwitchOn);
    if (target == PdsState::SwitchedOn) return;
    cmd(kEnableOp);
  }
};

TEST(CommandDecode, PatternsOfTable30) {
  EXPECT_EQ(decode_command(0x0006), Command::Shutdown);
  EXPECT_EQ(decode_command(0x000E), Command::Shutdown);  // bit 3 is "x"
  EXPECT_EQ(decode_command(0x0007), Command::SwitchOn);
  EXPECT_EQ(decode_command(0x000F), Command::EnableOperation);
  EXPECT_EQ(decode_command(0x0000), Command::DisableVoltage);
  EXPECT_EQ(decode_command(0x000D), Command::DisableVoltage);  // bit 1 clear: x x 0 x
  EXPECT_EQ(decode_command(0x0002), Command::QuickStop);
  EXPECT_EQ(decode_command(0x000B), Command::QuickStop);  // x 0 1 x
  EXPECT_EQ(decode_command(0x0086), Command::None);       // bit 7 set
  EXPECT_EQ(decode_command(0x010F), Command::EnableOperation);  // halt is not a device command
}

TEST(StateMachine, StartsNotReadyThenSwitchOnDisabled) {
  Sm s;
  EXPECT_EQ(s.sm.state(), PdsState::NotReadyToSwitchOn);
  EXPECT_EQ(s.sm.last_transition(), 0);
  EXPECT_EQ(s.cmd(kEnableOp), 1);  // no command is taken before transition 1
  EXPECT_EQ(s.sm.state(), PdsState::SwitchOnDisabled);
}

TEST(StateMachine, EnableSequenceTransitions2To4) {
  Sm s;
  s.to(PdsState::SwitchOnDisabled);
  EXPECT_EQ(s.cmd(kShutdown), 2);
  EXPECT_EQ(s.sm.state(), PdsState::ReadyToSwitchOn);
  EXPECT_EQ(s.cmd(kSwitchOn), 3);
  EXPECT_EQ(s.sm.state(), PdsState::SwitchedOn);
  EXPECT_EQ(s.cmd(kEnableOp), 4);
  EXPECT_EQ(s.sm.state(), PdsState::OperationEnabled);
  EXPECT_TRUE(s.sm.power_stage_on());
  EXPECT_TRUE(s.sm.operation_active());
}

TEST(StateMachine, SwitchOnAndEnableFromReadyToSwitchOn) {
  Sm s;
  s.to(PdsState::ReadyToSwitchOn);
  EXPECT_EQ(s.cmd(kEnableOp), 4);  // 3 + 4 in one go
  EXPECT_EQ(s.sm.state(), PdsState::OperationEnabled);
}

TEST(StateMachine, DisableOperationTransition5WithCoastOption) {
  Sm s;
  s.in.disable_operation_option = 0;
  s.to(PdsState::OperationEnabled);
  EXPECT_EQ(s.cmd(kDisableOp), 5);
  EXPECT_EQ(s.sm.state(), PdsState::SwitchedOn);
}

TEST(StateMachine, DisableOperationWithRampWaitsForStandstill) {
  Sm s;
  s.in.disable_operation_option = 1;
  s.to(PdsState::OperationEnabled);
  s.in.motion_stopped = false;
  EXPECT_EQ(s.cmd(kDisableOp), StateMachine::kNoTransition);
  EXPECT_EQ(s.sm.state(), PdsState::OperationEnabled);
  EXPECT_EQ(s.sm.stop(), StopKind::SlowDownRamp);
  EXPECT_FALSE(s.sm.operation_active());
  s.in.motion_stopped = true;
  EXPECT_EQ(s.cmd(kDisableOp), 5);
  EXPECT_EQ(s.sm.state(), PdsState::SwitchedOn);
  EXPECT_EQ(s.sm.stop(), StopKind::None);
}

TEST(StateMachine, ShutdownTransitions6And8) {
  Sm s;
  s.to(PdsState::SwitchedOn);
  EXPECT_EQ(s.cmd(kShutdown), 6);
  EXPECT_EQ(s.sm.state(), PdsState::ReadyToSwitchOn);
  s.cmd(kEnableOp);
  s.in.shutdown_option = 0;
  EXPECT_EQ(s.cmd(kShutdown), 8);
  EXPECT_EQ(s.sm.state(), PdsState::ReadyToSwitchOn);
}

TEST(StateMachine, ShutdownWithSlowDownRamp) {
  Sm s;
  s.in.shutdown_option = 1;
  s.to(PdsState::OperationEnabled);
  s.in.motion_stopped = false;
  EXPECT_EQ(s.cmd(kShutdown), StateMachine::kNoTransition);
  EXPECT_EQ(s.sm.stop(), StopKind::SlowDownRamp);
  s.in.motion_stopped = true;
  EXPECT_EQ(s.cmd(kShutdown), 8);
}

TEST(StateMachine, Transition7ByDisableVoltageOrQuickStop) {
  for (std::uint16_t c : {kDisableVoltage, kQuickStop}) {
    Sm s;
    s.to(PdsState::ReadyToSwitchOn);
    EXPECT_EQ(s.cmd(c), 7);
    EXPECT_EQ(s.sm.state(), PdsState::SwitchOnDisabled);
  }
}

TEST(StateMachine, Transition9DisableVoltageFromOperationEnabled) {
  Sm s;
  s.to(PdsState::OperationEnabled);
  EXPECT_EQ(s.cmd(kDisableVoltage), 9);
  EXPECT_EQ(s.sm.state(), PdsState::SwitchOnDisabled);
  EXPECT_FALSE(s.sm.power_stage_on());
}

TEST(StateMachine, Transition10FromSwitchedOn) {
  for (std::uint16_t c : {kDisableVoltage, kQuickStop}) {
    Sm s;
    s.to(PdsState::SwitchedOn);
    EXPECT_EQ(s.cmd(c), 10);
    EXPECT_EQ(s.sm.state(), PdsState::SwitchOnDisabled);
  }
}

TEST(StateMachine, QuickStopRampThenSwitchOnDisabled11And12) {
  Sm s;
  s.in.quick_stop_option = 2;
  s.to(PdsState::OperationEnabled);
  s.in.motion_stopped = false;
  EXPECT_EQ(s.cmd(kQuickStop), 11);
  EXPECT_EQ(s.sm.state(), PdsState::QuickStopActive);
  EXPECT_EQ(s.sm.stop(), StopKind::QuickStopRamp);
  EXPECT_EQ(s.cmd(kQuickStop), StateMachine::kNoTransition);
  s.in.motion_stopped = true;
  EXPECT_EQ(s.cmd(kQuickStop), 12);
  EXPECT_EQ(s.sm.state(), PdsState::SwitchOnDisabled);
}

TEST(StateMachine, QuickStopOption0DisablesAtOnce) {
  Sm s;
  s.in.quick_stop_option = 0;
  s.to(PdsState::OperationEnabled);
  EXPECT_EQ(s.cmd(kQuickStop), 12);
  EXPECT_EQ(s.sm.state(), PdsState::SwitchOnDisabled);
}

TEST(StateMachine, QuickStopStayAndTransition16) {
  Sm s;
  s.in.quick_stop_option = 6;
  s.to(PdsState::OperationEnabled);
  s.in.motion_stopped = false;
  EXPECT_EQ(s.cmd(kQuickStop), 11);
  s.in.motion_stopped = true;
  EXPECT_EQ(s.cmd(kQuickStop), StateMachine::kNoTransition);  // stays
  EXPECT_EQ(s.sm.state(), PdsState::QuickStopActive);
  EXPECT_EQ(s.cmd(kEnableOp), 16);
  EXPECT_EQ(s.sm.state(), PdsState::OperationEnabled);
}

TEST(StateMachine, QuickStopActiveDisableVoltageIs12) {
  Sm s;
  s.in.quick_stop_option = 5;
  s.to(PdsState::OperationEnabled);
  s.cmd(kQuickStop);
  EXPECT_EQ(s.cmd(kDisableVoltage), 12);
}

TEST(StateMachine, FaultReactionFaultAndReset13To15) {
  Sm s;
  s.in.fault_reaction_option = 2;
  s.to(PdsState::OperationEnabled);
  s.in.fault = true;
  s.in.motion_stopped = false;
  EXPECT_EQ(s.cmd(kEnableOp), 13);
  EXPECT_EQ(s.sm.state(), PdsState::FaultReactionActive);
  EXPECT_EQ(s.sm.stop(), StopKind::QuickStopRamp);
  EXPECT_EQ(s.cmd(kEnableOp), StateMachine::kNoTransition);
  s.in.motion_stopped = true;
  EXPECT_EQ(s.cmd(kEnableOp), 14);
  EXPECT_EQ(s.sm.state(), PdsState::Fault);
  // Reset only on the rising edge, and only once the fault is gone.
  EXPECT_EQ(s.cmd(kFaultReset), StateMachine::kNoTransition);
  s.in.fault = false;
  EXPECT_EQ(s.cmd(kFaultReset), StateMachine::kNoTransition);  // still high: no edge
  s.cmd(0);
  EXPECT_EQ(s.cmd(kFaultReset), 15);
  EXPECT_EQ(s.sm.state(), PdsState::SwitchOnDisabled);
}

TEST(StateMachine, FaultInSwitchOnDisabledGoesStraightToFault) {
  Sm s;
  s.to(PdsState::SwitchOnDisabled);
  s.in.fault = true;
  EXPECT_EQ(s.cmd(0), 13);
  EXPECT_EQ(s.sm.stop(), StopKind::Coast);
  EXPECT_EQ(s.cmd(0), 14);
}

TEST(StateMachine, ForbiddenCommandsAreIgnored) {
  Sm s;
  s.to(PdsState::SwitchOnDisabled);
  EXPECT_EQ(s.cmd(kSwitchOn), StateMachine::kNoTransition);
  EXPECT_EQ(s.cmd(kEnableOp), StateMachine::kNoTransition);
  EXPECT_EQ(s.cmd(kQuickStop), StateMachine::kNoTransition);
  EXPECT_EQ(s.sm.state(), PdsState::SwitchOnDisabled);
  s.cmd(kShutdown);
  EXPECT_EQ(s.cmd(kShutdown | kFaultReset), StateMachine::kNoTransition);  // bit 7: no command
  EXPECT_EQ(s.sm.state(), PdsState::ReadyToSwitchOn);
  s.cmd(kSwitchOn);
  s.cmd(kEnableOp);
  EXPECT_EQ(s.cmd(kFaultReset), StateMachine::kNoTransition);  // reset without fault does nothing
  EXPECT_EQ(s.sm.state(), PdsState::OperationEnabled);
}

TEST(StatusWord, BitsPerStateTable32) {
  EXPECT_EQ(state_bits(PdsState::NotReadyToSwitchOn) & sw::kStateMaskNoQs, 0x0000);
  EXPECT_EQ(state_bits(PdsState::SwitchOnDisabled) & sw::kStateMaskNoQs, 0x0040);
  EXPECT_EQ(state_bits(PdsState::ReadyToSwitchOn) & sw::kStateMask, 0x0021);
  EXPECT_EQ(state_bits(PdsState::SwitchedOn) & sw::kStateMask, 0x0023);
  EXPECT_EQ(state_bits(PdsState::OperationEnabled) & sw::kStateMask, 0x0027);
  EXPECT_EQ(state_bits(PdsState::QuickStopActive) & sw::kStateMask, 0x0007);
  EXPECT_EQ(state_bits(PdsState::FaultReactionActive) & sw::kStateMaskNoQs, 0x000F);
  EXPECT_EQ(state_bits(PdsState::Fault) & sw::kStateMaskNoQs, 0x0008);
}

}  // namespace
}  // namespace ecat::ds402
