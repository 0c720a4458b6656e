#include "transport/ip_allow_list.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>

#include <cstring>

#include <fmt/format.h>

namespace ecat::transport {
namespace {

using Address = std::array<std::uint8_t, IpPrefix::kAddressBytes>;

constexpr std::size_t kMappedMarkerOffset = 10;  // ::ffff:a.b.c.d: bytes 10-11 are 0xFF
constexpr std::size_t kMappedIpv4Offset = 12;    // the IPv4 address in bytes 12-15
constexpr unsigned kBitsPerByte = 8;
// Longest numeric address inet_pton may be given (INET6_ADDRSTRLEN includes the NUL).
constexpr std::size_t kMaxAddressText = INET6_ADDRSTRLEN - 1;

Address mapped(const in_addr& v4) noexcept {
  Address a{};
  a[kMappedMarkerOffset] = 0xFF;
  a[kMappedMarkerOffset + 1] = 0xFF;
  std::memcpy(a.data() + kMappedIpv4Offset, &v4, sizeof v4);
  return a;
}

// Plain decimal 0..max, no sign, no leading zero (except "0" itself).
bool parse_length(std::string_view text, unsigned max, unsigned& out) noexcept {
  if (text.empty() || text.size() > 3 || (text.size() > 1 && text.front() == '0')) return false;
  unsigned v = 0;
  for (char c : text) {
    if (c < '0' || c > '9') return false;
    v = v * 10 + static_cast<unsigned>(c - '0');
  }
  if (v > max) return false;
  out = v;
  return true;
}

// The bits of `a` after the first `length` ones are all zero.
bool host_bits_clear(const Address& a, unsigned length) noexcept {
  for (unsigned bit = length; bit < IpPrefix::kIpv6Bits; ++bit) {
    if ((a[bit / kBitsPerByte] >> (kBitsPerByte - 1 - bit % kBitsPerByte)) & 1u) return false;
  }
  return true;
}

}  // namespace

bool IpPrefix::contains(const Address& a) const noexcept {
  const unsigned whole = length / kBitsPerByte;
  if (std::memcmp(address.data(), a.data(), whole) != 0) return false;
  const unsigned rest = length % kBitsPerByte;
  if (rest == 0) return true;
  const auto mask = static_cast<std::uint8_t>(0xFFu << (kBitsPerByte - rest));
  return (address[whole] & mask) == (a[whole] & mask);
}

Expected<IpPrefix, std::string> parse_ip_prefix(std::string_view text) {
  const auto slash = text.find('/');
  const std::string_view host = text.substr(0, slash);
  if (host.empty() || host.size() > kMaxAddressText) {
    return fail(fmt::format("'{}': not an IPv4 or IPv6 address", text));
  }
  const std::string host_z(host);
  IpPrefix p;
  unsigned max = 0;
  unsigned offset = 0;  // bits of the mapped prefix in front of an IPv4 address
  in_addr v4{};
  in6_addr v6{};
  if (::inet_pton(AF_INET, host_z.c_str(), &v4) == 1) {
    p.address = mapped(v4);
    max = IpPrefix::kIpv4Bits;
    offset = IpPrefix::kMappedIpv4Bits;
  } else if (::inet_pton(AF_INET6, host_z.c_str(), &v6) == 1) {
    std::memcpy(p.address.data(), &v6, sizeof v6);
    max = IpPrefix::kIpv6Bits;
  } else {
    return fail(fmt::format("'{}': not an IPv4 or IPv6 address", text));
  }
  unsigned length = max;
  if (slash != std::string_view::npos && !parse_length(text.substr(slash + 1), max, length)) {
    return fail(fmt::format("'{}': prefix length must be 0..{}", text, max));
  }
  p.length = offset + length;
  if (!host_bits_clear(p.address, p.length)) {
    return fail(fmt::format("'{}': address bits set beyond the /{} prefix", text, length));
  }
  return p;
}

bool ip_of(const sockaddr_storage& address, Address& out) noexcept {
  if (address.ss_family == AF_INET) {
    out = mapped(reinterpret_cast<const sockaddr_in*>(&address)->sin_addr);
    return true;
  }
  if (address.ss_family == AF_INET6) {
    std::memcpy(out.data(), &reinterpret_cast<const sockaddr_in6*>(&address)->sin6_addr, out.size());
    return true;
  }
  return false;
}

Expected<IpAllowList, std::string> IpAllowList::parse(std::string_view text) {
  IpAllowList list;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = text.find(',', start);
    const std::string_view item = text.substr(start, comma == std::string_view::npos ? comma : comma - start);
    if (item.empty()) return fail(fmt::format("'{}': empty entry in the list", text));
    auto p = parse_ip_prefix(item);
    if (!p) return fail(p.error());
    list.add(*p);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return list;
}

bool IpAllowList::allows(const Address& address) const noexcept {
  for (const IpPrefix& p : prefixes_) {
    if (p.contains(address)) return true;
  }
  return false;
}

bool IpAllowList::allows(const sockaddr_storage& peer) const noexcept {
  Address a{};
  return ip_of(peer, a) && allows(a);
}

}  // namespace ecat::transport
