// The fault catalogue (issue 26 item 2): faults a test or the control
// interface engages on a running chain and clears again - a cable cut, lost
// or corrupted frames, a wrong working counter, an AL error, a refused
// transition, a watchdog expiry, a drive fault - each acting where the
// silicon or firmware of a real slave would show it, so the master reads
// the same bytes and codes it would read from a faulty network.
// docs/faults.md lists every kind: its parameters, what the master sees and
// the spec clause.
//
// Frame faults act where frames enter and leave the chain: a user that
// wants them passes frames through FaultCatalogue::pass_frame_on (or
// process_frame) instead of Chain's. With nothing engaged that costs one
// predictable branch per frame (docs/faults.md "Cost").
//
// Bad input (unknown kind, slave, port or parameter, a value out of range)
// is refused with a message that says what is wrong, and nothing changes.
// Not thread-safe: call it from the thread that runs the chain (between
// frames), as ecat-slave's live loop does.
//
// drop_frames for one slave matches the station address 0x0010 it had
// when the fault was engaged (and its position for APxx).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "common/clock.hpp"
#include "common/expected.hpp"
#include "esc/segment.hpp"
#include "slave/chain.hpp"

namespace ecat::slave {

struct FaultRequest {
  std::string kind;                             // catalogue name, e.g. "link_cut", "drop_frames"
  std::optional<std::size_t> slave;             // position in the chain (0-based), where the fault has one
  std::optional<unsigned> port;                 // ESC port 0..3, where the fault has one
  std::map<std::string, std::int64_t> params;  // named numbers: "count", "code", ...
};

struct FaultParam {
  std::string_view name;
  std::string_view meaning;  // one line, with the default when it is optional
  bool required = false;
};

// One row of the catalogue.
struct FaultKind {
  std::string_view name;
  std::string_view description;  // one line, what the master then sees
  bool needs_slave = false;
  bool needs_port = false;
  std::span<const FaultParam> params;
  bool takes_slave = false;  // a slave is optional (needs_slave implies it)
};

using FaultId = std::uint32_t;

struct EngagedFault {
  FaultId id = 0;
  FaultRequest request;
};

class FaultCatalogue {
 public:
  // Called on every engage and clear (engaged = false), also when a fault
  // that counts frames is spent and clears itself (then from inside
  // pass_frame_on).
  using Observer = std::function<void(const EngagedFault&, bool engaged)>;

  explicit FaultCatalogue(Chain& chain);
  // Clears every engaged fault (cables restored, ...).
  ~FaultCatalogue();
  FaultCatalogue(const FaultCatalogue&) = delete;
  FaultCatalogue& operator=(const FaultCatalogue&) = delete;

  // Every kind engage() accepts, in the order of docs/faults.md.
  static std::span<const FaultKind> kinds() noexcept;
  static const FaultKind* find_kind(std::string_view name) noexcept;

  // Engages a fault; a clear message for an unknown kind/slave/port/param
  // or a value out of range, and nothing changes then.
  Expected<FaultId, std::string> engage(const FaultRequest& request);
  // Clears an engaged fault (undoes what engage did, as far as the fault
  // has not already run its course: a latched AL error stays until the
  // master acknowledges it, as on a real slave).
  Expected<void, std::string> clear(FaultId id);
  void clear_all();
  std::vector<EngagedFault> engaged() const;

  void set_observer(Observer observer) { observer_ = std::move(observer); }

  // --- The frame path ---
  // Chain::pass_frame_on with the engaged frame faults applied: a frame a
  // fault drops comes back as esc::Delivery::Outcome::Lost (send nothing);
  // a returned frame may have had its working counters changed in place.
  esc::Delivery pass_frame_on(std::span<std::uint8_t> frame, Nanoseconds now, unsigned master_port) noexcept {
    if (frame_faults_ == 0) [[likely]] {
      return chain_.pass_frame_on(frame, now, master_port);
    }
    return pass_faulty(frame, now, master_port);
  }
  // Chain::process_frame the same way: pass_frame_on(port 0), then the firmware.
  bool process_frame(std::span<std::uint8_t> frame, Nanoseconds now) noexcept {
    const bool returned = pass_frame_on(frame, now, 0).returned();
    chain_.run_firmware(now);
    return returned;
  }

  // Replies the reply faults (delay_frames, duplicate_frames, replay_frames)
  // send later or besides the frames pass_frame_on returned: the owner of
  // the transport sends each one take_reply copies into `out` (room for
  // faults::ReplyFaults::kMaxFrame bytes) on its master port, after every
  // frame and when next_reply_due comes. Nothing waits: nullopt, cheaply.
  struct HeldReply {
    std::size_t length = 0;
    unsigned master_port = 0;
  };
  std::optional<HeldReply> take_reply(Nanoseconds now, std::span<std::uint8_t> out) noexcept;
  std::optional<Nanoseconds> next_reply_due() const noexcept;

  Chain& chain() noexcept { return chain_; }

 private:
  struct Impl;  // the engaged faults' state (slave/fault_catalogue.cpp, slave/faults/)
  esc::Delivery pass_faulty(std::span<std::uint8_t> frame, Nanoseconds now, unsigned master_port) noexcept;

  Chain& chain_;
  std::unique_ptr<Impl> impl_;
  Observer observer_;
  unsigned frame_faults_ = 0;  // engaged faults that act on the frame path
};

}  // namespace ecat::slave
