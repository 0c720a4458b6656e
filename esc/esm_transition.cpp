// ETG.1000.6 §6.4.1: the allowed transitions. Anything missing here between
// two different states is refused with 0x0011 (I->S, I->O, P->O, P->B,
// B->P/S/O, S->B, O->B; shared/spec/esm-al-codes.md §2).
#include "esc/esm_transition.hpp"

#include <array>

namespace ecat::esc {
namespace {

struct Entry {
  AlState from;
  AlState to;
  EsmTransition transition;
};

constexpr std::array kTable{
    Entry{AlState::Init, AlState::PreOp, EsmTransition::IP},
    Entry{AlState::Init, AlState::Bootstrap, EsmTransition::IB},
    Entry{AlState::Bootstrap, AlState::Init, EsmTransition::BI},
    Entry{AlState::PreOp, AlState::Init, EsmTransition::PI},
    Entry{AlState::PreOp, AlState::SafeOp, EsmTransition::PS},
    Entry{AlState::SafeOp, AlState::PreOp, EsmTransition::SP},
    Entry{AlState::SafeOp, AlState::Op, EsmTransition::SO},
    Entry{AlState::SafeOp, AlState::Init, EsmTransition::SI},
    Entry{AlState::Op, AlState::SafeOp, EsmTransition::OS},
    Entry{AlState::Op, AlState::PreOp, EsmTransition::OP},
    Entry{AlState::Op, AlState::Init, EsmTransition::OI},
};

}  // namespace

std::optional<AlState> decode_al_state(std::uint8_t code) noexcept {
  switch (code) {
    case static_cast<std::uint8_t>(AlState::Init): return AlState::Init;
    case static_cast<std::uint8_t>(AlState::PreOp): return AlState::PreOp;
    case static_cast<std::uint8_t>(AlState::Bootstrap): return AlState::Bootstrap;
    case static_cast<std::uint8_t>(AlState::SafeOp): return AlState::SafeOp;
    case static_cast<std::uint8_t>(AlState::Op): return AlState::Op;
    default: return std::nullopt;
  }
}

EsmTransition lookup_transition(AlState from, AlState to) noexcept {
  if (from == to) return EsmTransition::Stay;
  for (const Entry& e : kTable) {
    if (e.from == from && e.to == to) return e.transition;
  }
  return EsmTransition::Refused;
}

bool is_downward(EsmTransition t) noexcept {
  switch (t) {
    case EsmTransition::BI:
    case EsmTransition::PI:
    case EsmTransition::SP:
    case EsmTransition::OS:
    case EsmTransition::SI:
    case EsmTransition::OP:
    case EsmTransition::OI: return true;
    default: return false;
  }
}

}  // namespace ecat::esc
