// Sends datagrams in one frame and waits for the reply with the same index
// (ETG.1000.4 §5.4: slaves never change the index byte). Replies with another
// index are stale and skipped; no reply within the frame timeout -> the frame
// is sent again (SOEM re-sends the same way), up to `retries` times. Buffers
// are fixed at construction: nothing allocates per frame.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "common/clock.hpp"
#include "common/command.hpp"
#include "common/expected.hpp"
#include "common/frame.hpp"
#include "master/master_error.hpp"
#include "transport/transport.hpp"

namespace ecat::master {

// One datagram of an exchange: `data` is sent and replaced with the reply data.
struct Datagram {
  Command command = Command::Nop;
  std::uint32_t address = 0;  // device_address(adp, ado) or a logical address
  Bytes data;
  std::uint16_t wkc = 0;      // filled from the reply
};

struct LinkConfig {
  Nanoseconds frame_timeout = std::chrono::milliseconds(20);
  unsigned retries = 3;
  MacAddress source = {0x01, 0x01, 0x01, 0x01, 0x01, 0x01};  // as SOEM
};

struct LinkStats {
  std::uint64_t frames_sent = 0;
  std::uint64_t frames_received = 0;
  std::uint64_t timeouts = 0;
  std::uint64_t stale_replies = 0;
};

class DatagramLink {
 public:
  DatagramLink(transport::Transport& transport, const Clock& clock, LinkConfig config = {}) noexcept
      : transport_(transport), clock_(clock), config_(config) {}

  // All datagrams in one frame; on success each gets its reply data and WKC.
  Expected<void, MasterError> exchange(std::span<Datagram> datagrams);
  // One datagram; returns its WKC.
  Expected<std::uint16_t, MasterError> exchange(Command command, std::uint32_t address, Bytes data);
  // Any number of datagrams, in order, packed into as few frames as the
  // Ethernet frame limit allows (each frame: consecutive datagrams whose
  // headers, data and WKCs fit kMaxEthernetPayload after the frame header),
  // one frame after the other (ETG.1000.4 §5.3: a frame carries any number of
  // datagrams; SOEM and TwinCAT batch the per-slave reads of the scan so).
  // Returns the number of frames used; each datagram gets its reply and WKC.
  Expected<std::size_t, MasterError> exchange_batch(std::span<Datagram> datagrams);
  // How many of `datagrams`, from the first, fit one frame (at least 1 if the
  // first fits at all, 0 if it does not).
  static std::size_t fitting_in_one_frame(std::span<const Datagram> datagrams) noexcept;

  const LinkStats& stats() const noexcept { return stats_; }
  const LinkConfig& config() const noexcept { return config_; }
  const Clock& clock() const noexcept { return clock_; }
  transport::Transport& transport() noexcept { return transport_; }
  transport::TransportError last_transport_error() const noexcept { return last_transport_error_; }

 private:
  bool matches(Bytes reply, std::uint8_t index, std::span<const Datagram> sent) const noexcept;

  transport::Transport& transport_;
  const Clock& clock_;
  LinkConfig config_;
  LinkStats stats_{};
  std::uint8_t next_index_ = 0;
  transport::TransportError last_transport_error_ = transport::TransportError::Timeout;
  std::array<std::uint8_t, transport::kMaxFrameSize> tx_{};
  std::array<std::uint8_t, transport::kMaxFrameSize> rx_{};
};

}  // namespace ecat::master
