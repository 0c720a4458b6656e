// The frame faults of slave::FaultCatalogue (docs/faults.md): frames lost
// on the way to the slaves or on the way back (all, or only those that carry
// a datagram for one slave), and working counters off by a fixed offset for
// one command type. They act where a frame enters and leaves the chain;
// the catalogue asks them only while one is engaged.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "common/command.hpp"
#include "common/frame_parser.hpp"

namespace ecat::slave::faults {

using FrameFaultId = std::uint32_t;

// Frames lost: the next `left` frames (0: every frame until cleared).
struct DropRule {
  FrameFaultId id = 0;
  std::uint64_t left = 0;
  bool until_cleared = false;
  // Where the frame is lost: before the first slave (nothing processed) or
  // on its way back (the slaves processed it; the master never sees it).
  bool after = false;
  // Only frames carrying an APxx/FPxx datagram for this slave (always
  // lost on the way back): its position and station address 0x0010.
  std::optional<std::uint16_t> position;
  std::uint16_t station = 0;
};

// Working counters of every `command` datagram in a returned frame + offset
// (modulo 2^16, as the 16-bit field wraps), for `left` frames (or until cleared).
struct WkcRule {
  FrameFaultId id = 0;
  Command command = Command::Nop;
  std::int32_t offset = 0;
  std::uint64_t left = 0;
  bool until_cleared = false;
};

class FrameFaults {
 public:
  // Set-up of a rule (engage time): the lists the frame path fills are
  // reserved here, so the frame path allocates nothing.
  void add(const DropRule& r) {
    drops_.push_back(r);
    reserve();
  }
  void add(const WkcRule& r) {
    wkcs_.push_back(r);
    reserve();
  }
  // Removes the rule with that id; false if there is none.
  bool remove(FrameFaultId id) noexcept;
  bool empty() const noexcept { return drops_.empty() && wkcs_.empty(); }

  // Before the frame enters the chain: true when it is lost there.
  bool lose_before(std::span<std::uint8_t> frame) noexcept;
  // After it came back: true when it is lost now; else the WKC offsets are
  // applied in place.
  bool lose_after(std::span<std::uint8_t> frame) noexcept;
  // Rules spent by the last two calls (taken out of the set) until clear_spent.
  std::span<const FrameFaultId> spent() const noexcept { return spent_; }
  void clear_spent() noexcept { spent_.clear(); }

  // Whether a frame (as the master sent it) carries a datagram for the
  // slave at `position` with station address `station`.
  static bool addresses(const FrameView& frame, std::uint16_t position, std::uint16_t station) noexcept;

 private:
  // Counts one frame against a rule; true when it is spent.
  template <typename Rule>
  bool use(Rule& r) noexcept {
    if (r.until_cleared) return false;
    if (r.left > 0) --r.left;
    if (r.left != 0) return false;
    spent_.push_back(r.id);
    return true;
  }

  void reserve() {
    spent_.reserve(drops_.size() + wkcs_.size());
    matched_.reserve(drops_.size());
  }

  std::vector<DropRule> drops_;
  std::vector<WkcRule> wkcs_;
  std::vector<FrameFaultId> spent_;
  // Drop rules for one slave matched by the frame as it went in.
  std::vector<FrameFaultId> matched_;
};

}  // namespace ecat::slave::faults
