// The built-in Ethernet side of an EoE slave when nothing else is attached
// (docs/eoe.md): with the IP address the EoE server holds (Set IP Parameter
// or the start-up defaults), it answers ARP requests for that address
// (RFC 826) and ICMP echo requests to it (RFC 792) with checksums as
// RFC 1071 computes them, so a master's EoE path can be pinged with no
// set-up. Everything else is counted and ignored. Replies go back through
// EoeServer::transmit; the reply is built in one buffer, allocated on the
// first reply (a slave nobody pings does not carry it).
#pragma once

#include <array>
#include <cstdint>
#include <memory>

#include "coe/eoe_server.hpp"

namespace ecat::coe {

namespace ethernet {
inline constexpr std::size_t kHeaderSize = 14;
inline constexpr std::uint16_t kTypeIpv4 = 0x0800;
inline constexpr std::uint16_t kTypeArp = 0x0806;
inline constexpr std::uint16_t kArpHardwareEthernet = 1;
inline constexpr std::uint16_t kArpRequest = 1;
inline constexpr std::uint16_t kArpReply = 2;
inline constexpr std::size_t kArpSize = 28;
inline constexpr std::uint8_t kIpVersion4 = 4;
inline constexpr std::size_t kIpMinHeader = 20;
inline constexpr std::uint8_t kProtocolIcmp = 1;
inline constexpr std::uint8_t kIcmpEchoReply = 0;
inline constexpr std::uint8_t kIcmpEchoRequest = 8;
inline constexpr std::size_t kIcmpMinSize = 8;
inline constexpr std::uint8_t kReplyTtl = 64;

// RFC 1071 one's-complement sum of 16-bit big-endian words, complemented.
std::uint16_t internet_checksum(ConstBytes data) noexcept;
}  // namespace ethernet

class EoeResponder final : public EthernetPort {
 public:
  struct Stats {
    std::uint64_t arp_replies = 0;
    std::uint64_t echo_replies = 0;
    std::uint64_t ignored = 0;      // other traffic, other addresses
    std::uint64_t bad_checksum = 0;
    std::uint64_t no_memory = 0;    // the reply buffer could not be allocated
  };

  explicit EoeResponder(EoeServer& server) : server_(server) {}
  void receive(ConstBytes frame) noexcept override;
  const Stats& stats() const noexcept { return stats_; }

 private:
  void arp(ConstBytes frame) noexcept;
  void icmp(ConstBytes frame) noexcept;
  // The reply buffer, allocated on first use; nullptr (counted) when that failed.
  std::uint8_t* reply_buffer() noexcept;

  EoeServer& server_;
  Stats stats_;
  std::unique_ptr<std::array<std::uint8_t, eoe::kMaxFrame>> reply_;
};

}  // namespace ecat::coe
