// How the layers above the ESC take part in the EtherCAT state machine
// (ETG.1000.6 §6.4.1): they can refuse a transition with their own AL status
// code (e.g. CoE refuses PreOp->SafeOp when the PDO mapping does not fit
// SM2/SM3), and they learn of every state change. Registered at start-up.
#pragma once

#include "esc/al_status_code.hpp"

namespace ecat::esc {

class EsmHooks {
 public:
  virtual ~EsmHooks() = default;
  // Called before the ESM carries out `from` -> `to` (after its own checks
  // passed). Return AlStatusCode::NoError to allow it, or the code to refuse.
  virtual AlStatusCode check_transition(AlState from, AlState to) noexcept {
    (void)from;
    (void)to;
    return AlStatusCode::NoError;
  }
  // Called after the state changed (also for fall-backs the ESM makes on its
  // own, e.g. watchdog expiry Op -> SafeOp, with the code it set).
  virtual void on_state_changed(AlState from, AlState to, AlStatusCode code) noexcept {
    (void)from;
    (void)to;
    (void)code;
  }
};

}  // namespace ecat::esc
