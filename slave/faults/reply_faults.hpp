// The reply faults of slave::FaultCatalogue (docs/faults.md): a returned
// frame held back for a time (delay_frames), sent twice (duplicate_frames),
// or replaced by the reply before it (replay_frames; the first reply the
// rule sees goes out as it is, to have one before the next) - what a switch, a
// congested host or a broken NIC does to a master's frames. They act after
// the chain returned the frame; the frames they send later or in addition
// wait in a fixed outbox (sized at engage time: nothing allocates on the
// frame path) until the owner of the transport takes them (take_due).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "common/clock.hpp"

namespace ecat::slave::faults {

using ReplyFaultId = std::uint32_t;

struct ReplyRule {
  enum class Kind : std::uint8_t { Delay, Duplicate, Replay };
  ReplyFaultId id = 0;
  Kind kind = Kind::Delay;
  Nanoseconds delay{0};  // Delay: how long the reply is held
  std::uint64_t left = 0;
  bool until_cleared = false;
};

class ReplyFaults {
 public:
  // An Ethernet frame with a VLAN tag, without FCS: the largest frame a
  // transport hands over.
  static constexpr std::size_t kMaxFrame = 1518;
  // Frames that can wait at once; a delayed frame beyond them is lost, as
  // in a switch whose buffer is full.
  static constexpr std::size_t kOutboxFrames = 16;

  void add(const ReplyRule& r);
  bool remove(ReplyFaultId id) noexcept;
  bool empty() const noexcept { return rules_.empty(); }

  // After the chain returned `frame` at `now` on `master_port`: applies the
  // first rule that takes it. True when the frame must not be sent now (held
  // or replaced); frames to send later or besides wait in the outbox.
  bool after_return(std::span<const std::uint8_t> frame, unsigned master_port, Nanoseconds now) noexcept;

  struct Due {
    std::size_t length = 0;
    unsigned master_port = 0;
  };
  // The next frame whose time has come (oldest due first), copied into
  // `out` (at least kMaxFrame bytes); nullopt when none is due.
  std::optional<Due> take_due(Nanoseconds now, std::span<std::uint8_t> out) noexcept;
  // When the next waiting frame is due; nullopt when none waits.
  std::optional<Nanoseconds> next_due() const noexcept;
  // Frames lost because the outbox was full (counted, never silent).
  std::uint64_t overflowed() const noexcept { return overflowed_; }

  // Rules spent by after_return (taken out of the set) until clear_spent.
  std::span<const ReplyFaultId> spent() const noexcept { return spent_; }
  void clear_spent() noexcept { spent_.clear(); }

 private:
  struct Slot {
    std::array<std::uint8_t, kMaxFrame> bytes{};
    std::size_t length = 0;
    unsigned master_port = 0;
    Nanoseconds due{0};
    std::uint64_t order = 0;  // FIFO among frames due at the same time
    bool used = false;
  };
  bool hold(std::span<const std::uint8_t> frame, unsigned master_port, Nanoseconds due) noexcept;
  void remember(std::span<const std::uint8_t> frame, unsigned master_port) noexcept;

  std::vector<ReplyRule> rules_;
  std::vector<ReplyFaultId> spent_;
  std::vector<Slot> outbox_;  // kOutboxFrames slots while a rule is engaged
  Slot previous_;             // the last reply that went out (Replay sends it)
  bool have_previous_ = false;
  std::uint64_t next_order_ = 0;
  std::uint64_t overflowed_ = 0;
};

}  // namespace ecat::slave::faults
