// Cable redundancy with a two-port master (ETG.1000.4: the segment closed to
// a ring back to a second master port; masters.md; SOEM ecx_init_redundant,
// ecx_outframe_red, ecx_waitinframe_red). A Transport over two transports, so
// the Master and its DatagramLink run unchanged on top of it:
//
//   send():    the frame goes out of the primary port (source MAC word 1
//              marked primary) and a dummy BRD 0x0000:2 with the same index
//              out of the secondary port (source marked secondary).
//   receive(): intact ring — the frame went through every slave and comes
//              back on the secondary port: it is the reply (the dummy passes
//              the ring unprocessed, in on port 1 of each ESC, and comes back
//              on the primary port). Broken ring — each port gets its own
//              frame back: the primary frame was processed by the slaves
//              before the break, the dummy by those behind it; the returned
//              primary frame is sent again out of the secondary port, where
//              the slaves behind the break process it in position order
//              (they take a frame coming in on port 1 through the processing
//              unit once it returns from their closed port 0, ESC datasheet
//              Section I), and that is the reply: every datagram processed by
//              every slave once, auto-increment positions, FRMW and WKC as in
//              the intact ring. Primary cable cut — the dummy returns on the
//              secondary port and the original frame is sent out of it.
//              Secondary cable cut — the primary frame returns on its own
//              port: it is the reply.
//
// Why not a copy of the frame out of both ports merged per datagram: the
// slaves behind a break would see the copy with the auto-increment address of
// the wrong position, read 0x0910 before the reference clock wrote it (FRMW),
// and an LRW's input bytes would have to be merged byte by byte. SOEM resends
// for the same reason. Fixed buffers; nothing allocates per frame.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

#include "common/clock.hpp"
#include "common/frame.hpp"
#include "transport/transport.hpp"

namespace ecat::master {

// Source MAC words SOEM uses to tell where a frame was sent (its defaults
// 01:01:01:01:01:01 and 04:04:04:04:04:04). ESCs set bit 1 of the first
// source byte when they process a frame, so only bytes 2-3 are compared.
inline constexpr MacAddress kPrimarySourceMac{0x01, 0x01, 0x01, 0x01, 0x01, 0x01};
inline constexpr MacAddress kSecondarySourceMac{0x04, 0x04, 0x04, 0x04, 0x04, 0x04};

enum class RingState : std::uint8_t {
  Unknown = 0,            // nothing exchanged yet
  Intact = 1,             // primary frame came back on the secondary port
  Broken = 2,             // each port got its own frame back: a break between two slaves
  PrimaryLinkDown = 3,    // nothing back on the primary port, dummy back on the secondary
  SecondaryLinkDown = 4,  // primary frame back on its own port, nothing on the secondary
  NoReply = 5,            // neither port answered in time
};
std::string_view describe(RingState s) noexcept;

struct RedundancyStats {
  std::uint64_t intact = 0;
  std::uint64_t broken = 0;
  std::uint64_t primary_down = 0;
  std::uint64_t secondary_down = 0;
  std::uint64_t no_reply = 0;
  std::uint64_t resent = 0;  // frames sent again out of the secondary port
  std::uint64_t stale = 0;   // frames of other exchanges dropped
};

// Where a broken ring is broken, by positions (0-based): the last slave the
// primary port reaches and the first one reached through the secondary port.
struct RingBreak {
  std::size_t last_primary_side = 0;
  std::size_t first_secondary_side = 0;
};

class RedundantTransport final : public transport::Transport {
 public:
  // `clock` bounds the waits; when it does not move (a ManualClock) a wait ends
  // after `max_polls` polls of both ports.
  RedundantTransport(transport::Transport& primary, transport::Transport& secondary, const Clock& clock,
                     unsigned max_polls = 64) noexcept;

  Expected<void, transport::TransportError> send(ConstBytes frame) override;
  Expected<std::size_t, transport::TransportError> receive(Bytes buffer, Nanoseconds timeout) override;

  // How the last exchange went round the ring.
  RingState state() const noexcept { return state_; }
  // Slaves that processed the dummy on the secondary side (its BRD WKC) in
  // the last exchange that found the ring broken or the primary cable cut.
  std::uint16_t secondary_side_slaves() const noexcept { return secondary_side_slaves_; }
  // With the master's slave count: between which two slaves the ring is
  // broken (empty unless the last state was Broken and the counts agree).
  std::optional<RingBreak> ring_break(std::size_t slave_count) const noexcept;
  const RedundancyStats& stats() const noexcept { return stats_; }

 private:
  enum class Seen : std::uint8_t { Nothing, PrimaryFrame, SecondaryFrame };
  Seen poll(transport::Transport& port, Bytes into, std::size_t& length, Nanoseconds wait);
  Expected<std::size_t, transport::TransportError> resend_on_secondary(Bytes frame, Bytes buffer, Nanoseconds timeout);
  Expected<std::size_t, transport::TransportError> deliver(Bytes from, std::size_t length, Bytes buffer);
  void finish(RingState s) noexcept;

  transport::Transport& primary_;
  transport::Transport& secondary_;
  const Clock& clock_;
  unsigned max_polls_;
  bool pending_ = false;
  std::uint8_t index_ = 0;
  std::size_t tx_length_ = 0;
  std::size_t dummy_length_ = 0;
  RingState state_ = RingState::Unknown;
  // A frame came in on the port since the port was last found down.
  bool primary_heard_ = false;
  bool secondary_heard_ = false;
  std::uint16_t secondary_side_slaves_ = 0;
  RedundancyStats stats_{};
  std::array<std::uint8_t, transport::kMaxFrameSize> tx_{};
  std::array<std::uint8_t, kMinEthernetFrame> dummy_{};
  std::array<std::uint8_t, transport::kMaxFrameSize> rx_primary_{};
  std::array<std::uint8_t, transport::kMaxFrameSize> rx_secondary_{};
};

}  // namespace ecat::master
