// The state faults of slave::FaultCatalogue on one slave's ESM
// (docs/faults.md): an error condition that holds the slave at or below a
// state (al_error, watchdog_expiry: while engaged, a request above it is
// refused with the fault's code, as firmware whose cause persists refuses
// it - ETG.1000.6 §6.4.1.3), and refusals of the next upward transitions
// with a chosen code (refuse_transition). Registered on the ESM while a
// fault uses it (esc::Esm::add_hooks / remove_hooks).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "esc/al_status_code.hpp"
#include "esc/esm_hooks.hpp"

namespace ecat::slave::faults {

// The rank of a state in the ESM's order: Init < PreOp < (Bootstrap) < SafeOp < Op.
int al_rank(esc::AlState s) noexcept;

class EsmGuard final : public esc::EsmHooks {
 public:
  using Id = std::uint32_t;
  // Told when a refusal rule has refused its last transition.
  using Spent = std::function<void(Id)>;

  explicit EsmGuard(Spent spent) : spent_(std::move(spent)) {}

  // A condition that refuses any transition to a state above `ceiling` with `code`.
  void hold(Id id, esc::AlState ceiling, esc::AlStatusCode code) { holds_.push_back({id, ceiling, code}); }
  // Refuses the next `count` upward transitions (into `to` only, when given) with `code`.
  void refuse(Id id, std::optional<esc::AlState> to, esc::AlStatusCode code, unsigned count) {
    refusals_.push_back({id, to, code, count});
  }
  // Removes a hold or refusal; false if there is none with that id.
  bool remove(Id id) noexcept;
  bool empty() const noexcept { return holds_.empty() && refusals_.empty(); }

  esc::AlStatusCode check_transition(esc::AlState from, esc::AlState to) noexcept override;

 private:
  struct Hold {
    Id id;
    esc::AlState ceiling;
    esc::AlStatusCode code;
  };
  struct Refusal {
    Id id;
    std::optional<esc::AlState> to;
    esc::AlStatusCode code;
    unsigned left;
  };
  Spent spent_;
  std::vector<Hold> holds_;
  std::vector<Refusal> refusals_;
};

}  // namespace ecat::slave::faults
