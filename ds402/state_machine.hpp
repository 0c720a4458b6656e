// Power drive system (PDS) finite state automaton, CiA 402-2 §8.1 (IEC
// 61800-7-201 §6.2, Figure 8): eight states, transitions 0-16 taken on the
// controlword commands of Table 30, on a fault, and when a stop ramp ends.
// Pure logic: it tells the motion layer which stop to carry out and is told
// when the axis has stopped.
#pragma once

#include <cstdint>
#include <string_view>

#include "ds402/controlword.hpp"
#include "ds402/option_codes.hpp"
#include "ds402/statusword.hpp"

namespace ecat::ds402 {

enum class PdsState : std::uint8_t {
  NotReadyToSwitchOn,
  SwitchOnDisabled,
  ReadyToSwitchOn,
  SwitchedOn,
  OperationEnabled,
  QuickStopActive,
  FaultReactionActive,
  Fault,
};

std::string_view to_string(PdsState s) noexcept;

// Statusword bits 0-3, 5, 6 for a state (Table 32). Bit 5 ("quick stop") is 1
// in the three states where the quick stop is not active and the table fixes
// it; elsewhere it reads 0.
inline std::uint16_t state_bits(PdsState s) noexcept {
  switch (s) {
    case PdsState::NotReadyToSwitchOn: return sw::kNotReadyToSwitchOn;
    case PdsState::SwitchOnDisabled: return sw::kSwitchOnDisabledState;
    case PdsState::ReadyToSwitchOn: return sw::kReadyToSwitchOnState;
    case PdsState::SwitchedOn: return sw::kSwitchedOnState;
    case PdsState::OperationEnabled: return sw::kOperationEnabledState;
    case PdsState::QuickStopActive: return sw::kQuickStopActiveState;
    case PdsState::FaultReactionActive: return sw::kFaultReactionActiveState;
    case PdsState::Fault: return sw::kFaultState;
  }
  return 0;
}

class StateMachine {
 public:
  static constexpr int kNoTransition = -1;

  struct Inputs {
    std::uint16_t controlword = 0;
    bool fault = false;           // a fault is latched (transition 13)
    bool motion_stopped = false;  // the stop asked for by stop() has ended
    std::int16_t quick_stop_option = 2;         // 605Ah
    std::int16_t shutdown_option = 0;           // 605Bh
    std::int16_t disable_operation_option = 1;  // 605Ch
    std::int16_t fault_reaction_option = 2;     // 605Eh
  };

  // Transition 0 (start -> Not ready to switch on) happens here.
  StateMachine() noexcept = default;

  // Rising edge of controlword bit 7 against the previous step's controlword
  // (transition 15 is taken on the edge only). Call before step().
  bool fault_reset_edge(std::uint16_t controlword) const noexcept {
    return (controlword & cw::kFaultReset) && !(previous_controlword_ & cw::kFaultReset);
  }

  // One cycle. Returns the transition taken (CiA numbering) or kNoTransition.
  // At most one transition per step, except 3+4 ("switch on + enable
  // operation" from Ready to switch on) and 11+12 (quick stop with 605Ah=0),
  // which report the last one.
  int step(const Inputs& in) noexcept;

  PdsState state() const noexcept { return state_; }
  // Stop the motion layer must carry out now (None when no stop is pending).
  StopKind stop() const noexcept { return stop_; }
  // True while the power stage drives the motor (operation enabled, or a
  // ramped quick stop, fault reaction, shutdown or disable operation).
  bool power_stage_on() const noexcept {
    return state_ == PdsState::OperationEnabled ||
           ((state_ == PdsState::QuickStopActive || state_ == PdsState::FaultReactionActive) &&
            stop_ != StopKind::Coast);
  }
  // True in Operation enabled while no ramp-down to another state runs: the
  // selected mode of operation generates the set-points.
  bool operation_active() const noexcept {
    return state_ == PdsState::OperationEnabled && pending_ == PdsState::OperationEnabled;
  }
  int last_transition() const noexcept { return last_transition_; }

 private:
  int go(PdsState to, int transition) noexcept;
  int start_ramp(PdsState to, int transition, StopKind stop) noexcept;

  PdsState state_ = PdsState::NotReadyToSwitchOn;
  // While a 605Bh/605Ch ramp runs in Operation enabled: the state to enter
  // when the axis has stopped (== state_ when nothing is pending).
  PdsState pending_ = PdsState::OperationEnabled;
  int pending_transition_ = kNoTransition;
  StopKind stop_ = StopKind::None;
  std::uint16_t previous_controlword_ = 0;
  int last_transition_ = 0;
};

}  // namespace ecat::ds402
