// Which peers may talk to the UDP slave (`ecat-slave --udp-allow`): a list of
// address prefixes in CIDR notation (RFC 4632 for IPv4, RFC 4291 §2.3 for
// IPv6). EtherCAT-in-UDP (ETG.1000.4 §5.3) carries no authentication, so the
// source address is the only thing the slave can check (docs/security.md).
//
// Every prefix is kept as an IPv6 prefix: an IPv4 prefix a.b.c.d/n becomes
// the IPv4-mapped ::ffff:a.b.c.d/(96+n) (RFC 4291 §2.5.5.2), so an IPv4 peer
// matches it whether it reached an AF_INET socket or a dual-stack AF_INET6
// one. Parsing is strict: numeric addresses only (no host names, no zone
// "%eth0"), a prefix length of plain decimal digits without leading zeros,
// and no address bits set beyond the prefix ("10.0.0.1/8" is refused, write
// 10.0.0.0/8), so a typo is an error rather than a wider or narrower rule.
#pragma once

#include <sys/socket.h>

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "common/expected.hpp"

namespace ecat::transport {

struct IpPrefix {
  static constexpr std::size_t kAddressBytes = 16;
  static constexpr unsigned kIpv4Bits = 32;
  static constexpr unsigned kIpv6Bits = 128;
  static constexpr unsigned kMappedIpv4Bits = kIpv6Bits - kIpv4Bits;  // ::ffff:0:0/96

  std::array<std::uint8_t, kAddressBytes> address{};  // IPv6 or IPv4-mapped
  unsigned length = 0;                                // bits of `address` that must match (0..128)

  // Whether the 16-byte address `a` (IPv6 or IPv4-mapped) lies in the prefix.
  bool contains(const std::array<std::uint8_t, kAddressBytes>& a) const noexcept;
  friend bool operator==(const IpPrefix&, const IpPrefix&) = default;
};

// "192.0.2.0/24", "192.0.2.7" (= /32), "2001:db8::/32", "::1" (= /128).
// The error says what is wrong with the text.
Expected<IpPrefix, std::string> parse_ip_prefix(std::string_view text);

// The 16-byte form of a socket address (IPv4 as IPv4-mapped); false for any
// other family.
bool ip_of(const sockaddr_storage& address, std::array<std::uint8_t, IpPrefix::kAddressBytes>& out) noexcept;

class IpAllowList {
 public:
  // "CIDR[,CIDR...]"; empty entries are refused.
  static Expected<IpAllowList, std::string> parse(std::string_view text);

  void add(const IpPrefix& prefix) { prefixes_.push_back(prefix); }
  // No prefix (no --udp-allow given): allows() is false for everyone, and
  // UdpTransport then filters nothing.
  bool empty() const noexcept { return prefixes_.empty(); }
  bool allows(const sockaddr_storage& peer) const noexcept;
  bool allows(const std::array<std::uint8_t, IpPrefix::kAddressBytes>& address) const noexcept;
  const std::vector<IpPrefix>& prefixes() const noexcept { return prefixes_; }

 private:
  std::vector<IpPrefix> prefixes_;
};

}  // namespace ecat::transport
