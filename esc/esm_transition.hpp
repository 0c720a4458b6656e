// The EtherCAT state machine's transition table (ETG.1000.6 §6.4.1 Table 10;
// shared/spec/esm-al-codes.md §2). Every pair of states maps to one named
// transition or to "refused" (AL status code 0x0011); a request for the
// state the slave is already in is "stay".
#pragma once

#include <cstdint>
#include <optional>

#include "esc/al_status_code.hpp"

namespace ecat::esc {

// Names as ETG.1000.6 uses them: IP = Init->PreOp, PS = PreOp->SafeOp, ...
enum class EsmTransition : std::uint8_t {
  Stay,     // requested state == current state
  Refused,  // not in the table: 0x0011, current state + ErrInd
  IP,       // start mailbox
  IB,       // start bootstrap mailbox
  BI,       // leave bootstrap
  PI,       // stop mailbox
  PS,       // start input update
  SP,       // stop input update
  SO,       // start output update
  OS,       // stop output update
  SI,       // stop input update and mailbox
  OP,       // stop output and input update
  OI,       // stop everything
};

// State code from AL control bits 3:0, or nullopt if it is not 1/2/3/4/8
// (AL status code 0x0012 "unknown requested state").
std::optional<AlState> decode_al_state(std::uint8_t code) noexcept;

EsmTransition lookup_transition(AlState from, AlState to) noexcept;

// True if `to` offers fewer services than `from` (going down never needs checks).
bool is_downward(EsmTransition t) noexcept;

}  // namespace ecat::esc
