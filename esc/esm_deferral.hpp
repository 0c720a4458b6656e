// A participant that may need time before an upward transition can complete
// (the Beckhoff slave stack's "NOERROR_INWORK"): e.g. SafeOp->Op in DC mode
// waits until the application runs synchronised to SYNC0. While any deferral
// is not ready the ESM leaves AL status unchanged (no ErrInd) and asks again
// on every poll; masters simply keep polling 0x0130 (IgH waits 5 s, ethercrab
// and SOEM likewise). A participant that gives up refuses through its
// EsmHooks::check_transition, which the ESM also re-runs on every poll.
#pragma once

#include "esc/al_status_code.hpp"

namespace ecat::esc {

class EsmDeferral {
 public:
  virtual ~EsmDeferral() = default;
  virtual bool transition_ready(AlState from, AlState to) noexcept = 0;
};

}  // namespace ecat::esc
