#include "slave/faults/esm_guard.hpp"

#include <algorithm>

namespace ecat::slave::faults {

int al_rank(esc::AlState s) noexcept {
  switch (s) {
    case esc::AlState::Init:
      return 0;
    case esc::AlState::PreOp:
      return 1;
    case esc::AlState::Bootstrap:
      return 1;
    case esc::AlState::SafeOp:
      return 2;
    case esc::AlState::Op:
      return 3;
  }
  return 0;
}

bool EsmGuard::remove(Id id) noexcept {
  const std::size_t n = holds_.size() + refusals_.size();
  std::erase_if(holds_, [id](const Hold& h) { return h.id == id; });
  std::erase_if(refusals_, [id](const Refusal& r) { return r.id == id; });
  return holds_.size() + refusals_.size() != n;
}

esc::AlStatusCode EsmGuard::check_transition(esc::AlState from, esc::AlState to) noexcept {
  for (const Hold& h : holds_) {
    if (al_rank(to) > al_rank(h.ceiling)) return h.code;
  }
  if (al_rank(to) <= al_rank(from)) return esc::AlStatusCode::NoError;  // downward: always carried out
  for (auto it = refusals_.begin(); it != refusals_.end(); ++it) {
    if (it->to && *it->to != to) continue;
    const esc::AlStatusCode code = it->code;
    if (--it->left == 0) {
      const Id id = it->id;
      refusals_.erase(it);
      if (spent_) spent_(id);
    }
    return code;
  }
  return esc::AlStatusCode::NoError;
}

}  // namespace ecat::slave::faults
