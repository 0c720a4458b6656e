#include "ds402/state_machine.hpp"

#include "ds402/statusword.hpp"

namespace ecat::ds402 {

std::string_view to_string(PdsState s) noexcept {
  switch (s) {
    case PdsState::NotReadyToSwitchOn: return "Not ready to switch on";
    case PdsState::SwitchOnDisabled: return "Switch on disabled";
    case PdsState::ReadyToSwitchOn: return "Ready to switch on";
    case PdsState::SwitchedOn: return "Switched on";
    case PdsState::OperationEnabled: return "Operation enabled";
    case PdsState::QuickStopActive: return "Quick stop active";
    case PdsState::FaultReactionActive: return "Fault reaction active";
    case PdsState::Fault: return "Fault";
  }
  return "?";
}

int StateMachine::go(PdsState to, int transition) noexcept {
  state_ = to;
  pending_ = PdsState::OperationEnabled;
  pending_transition_ = kNoTransition;
  stop_ = StopKind::None;
  last_transition_ = transition;
  return transition;
}

// 605Bh/605Ch = 1: stay in Operation enabled while the axis ramps down, then
// take the transition (CiA 402-2 §8.4.4/§8.4.5).
int StateMachine::start_ramp(PdsState to, int transition, StopKind stop) noexcept {
  if (stop == StopKind::Coast) return go(to, transition);
  pending_ = to;
  pending_transition_ = transition;
  stop_ = stop;
  return kNoTransition;
}

int StateMachine::step(const Inputs& in) noexcept {
  const Command cmd = decode_command(in.controlword);
  const bool reset = fault_reset_edge(in.controlword);
  previous_controlword_ = in.controlword;

  // Transition 13: a fault in any state but the two fault states.
  if (in.fault && state_ != PdsState::FaultReactionActive && state_ != PdsState::Fault) {
    const bool was_driving = power_stage_on();
    go(PdsState::FaultReactionActive, 13);
    // A drive whose power stage is off has nothing to stop.
    stop_ = was_driving ? stop_for_fault(in.fault_reaction_option) : StopKind::Coast;
    return 13;
  }

  switch (state_) {
    case PdsState::NotReadyToSwitchOn:
      return go(PdsState::SwitchOnDisabled, 1);  // self-test done at once

    case PdsState::SwitchOnDisabled:
      if (cmd == Command::Shutdown) return go(PdsState::ReadyToSwitchOn, 2);
      return kNoTransition;

    case PdsState::ReadyToSwitchOn:
      if (cmd == Command::SwitchOn) return go(PdsState::SwitchedOn, 3);
      if (cmd == Command::EnableOperation) return go(PdsState::OperationEnabled, 4);  // 3 + 4
      if (cmd == Command::DisableVoltage || cmd == Command::QuickStop) return go(PdsState::SwitchOnDisabled, 7);
      return kNoTransition;

    case PdsState::SwitchedOn:
      if (cmd == Command::EnableOperation) return go(PdsState::OperationEnabled, 4);
      if (cmd == Command::Shutdown) return go(PdsState::ReadyToSwitchOn, 6);
      if (cmd == Command::DisableVoltage || cmd == Command::QuickStop) return go(PdsState::SwitchOnDisabled, 10);
      return kNoTransition;

    case PdsState::OperationEnabled:
      if (cmd == Command::DisableVoltage) return go(PdsState::SwitchOnDisabled, 9);
      if (cmd == Command::QuickStop) {
        go(PdsState::QuickStopActive, 11);
        stop_ = stop_for_quick_stop(in.quick_stop_option);
        if (stop_ == StopKind::Coast) return go(PdsState::SwitchOnDisabled, 12);
        return 11;
      }
      if (pending_ != PdsState::OperationEnabled) {
        if (in.motion_stopped) return go(pending_, pending_transition_);
        return kNoTransition;
      }
      if (cmd == Command::Shutdown) return start_ramp(PdsState::ReadyToSwitchOn, 8, stop_for_disable(in.shutdown_option));
      if (cmd == Command::SwitchOn)
        return start_ramp(PdsState::SwitchedOn, 5, stop_for_disable(in.disable_operation_option));
      return kNoTransition;

    case PdsState::QuickStopActive:
      if (cmd == Command::DisableVoltage) return go(PdsState::SwitchOnDisabled, 12);
      if (quick_stop_stays(in.quick_stop_option)) {
        if (cmd == Command::EnableOperation && in.motion_stopped) return go(PdsState::OperationEnabled, 16);
        return kNoTransition;
      }
      if (in.motion_stopped) return go(PdsState::SwitchOnDisabled, 12);
      return kNoTransition;

    case PdsState::FaultReactionActive:
      if (in.motion_stopped || stop_ == StopKind::Coast) return go(PdsState::Fault, 14);
      return kNoTransition;

    case PdsState::Fault:
      if (reset && !in.fault) return go(PdsState::SwitchOnDisabled, 15);
      return kNoTransition;
  }
  return kNoTransition;
}

}  // namespace ecat::ds402
