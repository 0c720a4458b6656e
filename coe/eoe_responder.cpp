#include "coe/eoe_responder.hpp"

#include <algorithm>
#include <cstring>
#include <new>

namespace ecat::coe {

namespace ethernet {

std::uint16_t internet_checksum(ConstBytes data) noexcept {
  std::uint32_t sum = 0;
  for (std::size_t i = 0; i + 1 < data.size(); i += 2) sum += static_cast<std::uint32_t>(data[i] << 8 | data[i + 1]);
  if (data.size() % 2) sum += static_cast<std::uint32_t>(data.back() << 8);
  while (sum >> 16) sum = (sum & 0xFFFF) + (sum >> 16);
  return static_cast<std::uint16_t>(~sum);
}

}  // namespace ethernet

namespace {

using namespace ethernet;

// Network byte order (big-endian) fields of Ethernet, ARP, IPv4 and ICMP.
std::uint16_t be16(const std::uint8_t* p) noexcept { return static_cast<std::uint16_t>(p[0] << 8 | p[1]); }
std::uint32_t be32(const std::uint8_t* p) noexcept {
  return static_cast<std::uint32_t>(p[0]) << 24 | static_cast<std::uint32_t>(p[1]) << 16 |
         static_cast<std::uint32_t>(p[2]) << 8 | p[3];
}
void put_be16(std::uint8_t* p, std::uint16_t v) noexcept {
  p[0] = static_cast<std::uint8_t>(v >> 8);
  p[1] = static_cast<std::uint8_t>(v);
}

// Offsets in the ARP packet (RFC 826) after the Ethernet header.
constexpr std::size_t kArpHtype = 0, kArpPtype = 2, kArpHlen = 4, kArpPlen = 5, kArpOper = 6, kArpSha = 8,
                      kArpSpa = 14, kArpTha = 18, kArpTpa = 24;
constexpr std::uint8_t kIpv4AddressSize = 4;
// Offsets in the IPv4 header (RFC 791).
constexpr std::size_t kIpVersionIhl = 0, kIpTotalLength = 2, kIpTtl = 8, kIpProtocol = 9, kIpChecksum = 10,
                      kIpSource = 12, kIpDestination = 16;
constexpr std::size_t kIcmpType = 0, kIcmpCode = 1, kIcmpChecksum = 2;
constexpr std::size_t kEthDestination = 0, kEthSource = 6, kEthType = 12;

}  // namespace

void EoeResponder::receive(ConstBytes frame) noexcept {
  const auto& ip = server_.ip_parameters();
  if (frame.size() < kHeaderSize || !(ip.flags & eoe::kHasIp) || !(ip.flags & eoe::kHasMac)) {
    return (void)++stats_.ignored;
  }
  switch (be16(frame.data() + kEthType)) {
    case kTypeArp: return arp(frame);
    case kTypeIpv4: return icmp(frame);
    default: ++stats_.ignored;
  }
}

std::uint8_t* EoeResponder::reply_buffer() noexcept {
  if (!reply_) reply_.reset(new (std::nothrow) std::array<std::uint8_t, eoe::kMaxFrame>);
  if (!reply_) return ++stats_.no_memory, nullptr;
  return reply_->data();
}

void EoeResponder::arp(ConstBytes frame) noexcept {
  const auto& ip = server_.ip_parameters();
  const std::uint8_t* a = frame.data() + kHeaderSize;
  if (frame.size() < kHeaderSize + kArpSize || be16(a + kArpHtype) != kArpHardwareEthernet ||
      be16(a + kArpPtype) != kTypeIpv4 || a[kArpHlen] != eoe::kMacSize || a[kArpPlen] != kIpv4AddressSize ||
      be16(a + kArpOper) != kArpRequest || be32(a + kArpTpa) != ip.ip) {
    return (void)++stats_.ignored;
  }
  // Same length as the request (a minimum-size frame keeps its padding).
  std::uint8_t* r = reply_buffer();
  if (r == nullptr) return;
  std::memcpy(r, frame.data(), frame.size());
  std::memcpy(r + kEthDestination, a + kArpSha, eoe::kMacSize);
  std::memcpy(r + kEthSource, ip.mac.data(), eoe::kMacSize);
  std::uint8_t* ra = r + kHeaderSize;
  put_be16(ra + kArpOper, kArpReply);
  std::memcpy(ra + kArpTha, a + kArpSha, eoe::kMacSize + kIpv4AddressSize);  // target := sender (MAC, IP)
  std::memcpy(ra + kArpSha, ip.mac.data(), eoe::kMacSize);
  std::memcpy(ra + kArpSpa, a + kArpTpa, kIpv4AddressSize);
  if (server_.transmit({r, frame.size()})) ++stats_.arp_replies;
}

void EoeResponder::icmp(ConstBytes frame) noexcept {
  const auto& ip = server_.ip_parameters();
  const std::uint8_t* h = frame.data() + kHeaderSize;
  const std::size_t avail = frame.size() - kHeaderSize;
  if (avail < kIpMinHeader || (h[kIpVersionIhl] >> 4) != kIpVersion4) return (void)++stats_.ignored;
  const std::size_t ihl = static_cast<std::size_t>(h[kIpVersionIhl] & 0x0F) * 4;
  const std::size_t total = be16(h + kIpTotalLength);
  if (ihl < kIpMinHeader || total < ihl + kIcmpMinSize || total > avail || h[kIpProtocol] != kProtocolIcmp ||
      be32(h + kIpDestination) != ip.ip) {
    return (void)++stats_.ignored;
  }
  if (internet_checksum({h, ihl}) != 0 || internet_checksum({h + ihl, total - ihl}) != 0) {
    return (void)++stats_.bad_checksum;
  }
  if (h[ihl + kIcmpType] != kIcmpEchoRequest || h[ihl + kIcmpCode] != 0) return (void)++stats_.ignored;
  std::uint8_t* r = reply_buffer();
  if (r == nullptr) return;
  std::memcpy(r, frame.data(), frame.size());
  std::memcpy(r + kEthDestination, frame.data() + kEthSource, eoe::kMacSize);
  std::memcpy(r + kEthSource, ip.mac.data(), eoe::kMacSize);
  std::uint8_t* rh = r + kHeaderSize;
  std::memcpy(rh + kIpDestination, h + kIpSource, kIpv4AddressSize);
  std::memcpy(rh + kIpSource, h + kIpDestination, kIpv4AddressSize);
  rh[kIpTtl] = kReplyTtl;
  put_be16(rh + kIpChecksum, 0);
  put_be16(rh + kIpChecksum, internet_checksum({rh, ihl}));
  rh[ihl + kIcmpType] = kIcmpEchoReply;
  put_be16(rh + ihl + kIcmpChecksum, 0);
  put_be16(rh + ihl + kIcmpChecksum, internet_checksum({rh + ihl, total - ihl}));
  if (server_.transmit({r, frame.size()})) ++stats_.echo_replies;
}

}  // namespace ecat::coe
