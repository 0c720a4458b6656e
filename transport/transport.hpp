// One interface for every way an EtherCAT frame leaves or enters the process
// (STYLE lesson 8): raw socket, UDP, pcap file, in-memory. A frame here is always
// a whole Ethernet II frame (destination, source, EtherType 0x88A4, EtherCAT
// header, datagrams); transports that carry less (UDP, ETG.1000.4 §5.3) add or
// strip the Ethernet header themselves. Errors are values.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

#include "common/clock.hpp"
#include "common/frame.hpp"
#include "common/expected.hpp"
#include "common/le.hpp"

namespace ecat::transport {

// EtherType of EtherCAT frames, also the UDP port of EtherCAT-in-UDP (ETG.1000.4 §5.2/§5.3).
inline constexpr std::uint16_t kEtherTypeEthercat = ecat::kEtherTypeEtherCat;
inline constexpr std::uint16_t kUdpPortEthercat = 0x88A4;
// Ethernet sizes come from the wire format (common/frame.hpp).
using ecat::kEthernetHeaderSize;
using ecat::kMacSize;
inline constexpr std::size_t kEtherTypeOffset = 12;
// Largest untagged Ethernet II frame without FCS (1500-byte payload).
inline constexpr std::size_t kMaxFrameSize = 1514;

enum class TransportError : std::uint8_t {
  Timeout = 1,         // nothing arrived within the timeout
  BufferTooSmall = 2,  // the frame does not fit the caller's buffer (it is dropped)
  FrameTooLarge = 3,   // send(): frame longer than the medium allows
  InvalidFrame = 4,    // not an EtherCAT Ethernet frame where one is required
  NotOpen = 5,         // the transport has no open handle
  EndOfFile = 6,       // pcap replay exhausted
  OpenFailed = 7,      // socket/interface/file could not be opened or bound
  SendFailed = 8,      // OS refused to send
  ReceiveFailed = 9,   // OS refused to receive
  PermissionDenied = 10,
  Dropped = 11,        // a datagram arrived and was dropped by policy (UDP device side: source, length)
  WriteFailed = 12,    // an output file took a short or failed write
};

std::string_view describe(TransportError e) noexcept;

// EtherType of an Ethernet II frame (big-endian on the wire), 0 if too short.
constexpr std::uint16_t ether_type_of(ConstBytes frame) noexcept {
  if (frame.size() < kEthernetHeaderSize) return 0;
  return static_cast<std::uint16_t>((frame[kEtherTypeOffset] << 8) | frame[kEtherTypeOffset + 1]);
}

// A frame taken from the medium: its length and, where the medium stamps
// frames (the kernel does on sockets: transport/socket_timestamp.hpp), when
// it arrived, on the steady clock (SteadyClock's time base).
struct Received {
  std::size_t length = 0;
  std::optional<Nanoseconds> arrival;
};

class Transport {
 public:
  virtual ~Transport() = default;
  // Sends one whole Ethernet frame.
  virtual Expected<void, TransportError> send(ConstBytes frame) = 0;
  // Waits at most `timeout` for one frame and copies it into `buffer`;
  // returns its length. A zero timeout polls.
  virtual Expected<std::size_t, TransportError> receive(Bytes buffer, Nanoseconds timeout) = 0;
  // receive() that also says when the frame arrived. Media that know no
  // arrival time (in-memory, pcap: they keep their own time) leave it empty.
  virtual Expected<Received, TransportError> receive_stamped(Bytes buffer, Nanoseconds timeout) {
    auto n = receive(buffer, timeout);
    if (!n) return fail(n.error());
    return Received{*n, std::nullopt};
  }
};

}  // namespace ecat::transport
