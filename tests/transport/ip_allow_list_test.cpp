#include "transport/ip_allow_list.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>

#include <gtest/gtest.h>

#include <cstring>

namespace ecat::transport {
namespace {

using Address = std::array<std::uint8_t, IpPrefix::kAddressBytes>;

sockaddr_storage v4(const char* text) {
  sockaddr_storage s{};
  auto* a = reinterpret_cast<sockaddr_in*>(&s);
  a->sin_family = AF_INET;
  EXPECT_EQ(::inet_pton(AF_INET, text, &a->sin_addr), 1) << text;
  return s;
}

sockaddr_storage v6(const char* text) {
  sockaddr_storage s{};
  auto* a = reinterpret_cast<sockaddr_in6*>(&s);
  a->sin6_family = AF_INET6;
  EXPECT_EQ(::inet_pton(AF_INET6, text, &a->sin6_addr), 1) << text;
  return s;
}

bool allows(const char* list, const sockaddr_storage& peer) {
  auto l = IpAllowList::parse(list);
  EXPECT_TRUE(l.has_value()) << list;
  return l && l->allows(peer);
}

TEST(IpPrefix, IPv4IsStoredMapped) {
  auto p = parse_ip_prefix("192.0.2.0/24");
  ASSERT_TRUE(p.has_value()) << p.error();
  EXPECT_EQ(p->address, (Address{0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xFF, 0xFF, 192, 0, 2, 0}));
  EXPECT_EQ(p->length, 96u + 24u);
  auto host = parse_ip_prefix("192.0.2.7");
  ASSERT_TRUE(host.has_value());
  EXPECT_EQ(host->length, 128u);  // a bare address is /32
  auto any4 = parse_ip_prefix("0.0.0.0/0");
  ASSERT_TRUE(any4.has_value());
  EXPECT_EQ(any4->length, 96u);  // every IPv4 address, no IPv6 one
}

TEST(IpPrefix, IPv6) {
  auto p = parse_ip_prefix("2001:db8::/32");
  ASSERT_TRUE(p.has_value()) << p.error();
  EXPECT_EQ(p->address, (Address{0x20, 0x01, 0x0d, 0xb8}));
  EXPECT_EQ(p->length, 32u);
  auto lo = parse_ip_prefix("::1");
  ASSERT_TRUE(lo.has_value());
  EXPECT_EQ(lo->length, 128u);
  EXPECT_EQ(lo->address[15], 1);
  auto all = parse_ip_prefix("::/0");
  ASSERT_TRUE(all.has_value());
  EXPECT_EQ(all->length, 0u);
  EXPECT_TRUE(parse_ip_prefix("fe80::/10").has_value());
}

TEST(IpPrefix, RefusesWhatIsNotExactlyAPrefix) {
  for (const char* bad : {"", "/24", "10.0.0.0/", "10.0.0.0/33", "::/129", "10.0.0.0/-1", "10.0.0.0/+8",
                          "10.0.0.0/08", "10.0.0.0/8/8", "10.0.0.0/ 8", "10.0.0.0/8x", "10.0.0", "10.0.0.256",
                          "010.0.0.1", "10.0.0.1/8", "192.0.2.128/24", "2001:db8::1/32", "fe80::1%eth0",
                          "localhost", " 10.0.0.1", "10.0.0.1 ", "1.2.3.4/1000", "::ffff:10.0.0.1/95x"}) {
    auto p = parse_ip_prefix(bad);
    EXPECT_FALSE(p.has_value()) << "'" << bad << "' was accepted";
  }
  // The message names the entry and the reason.
  auto host_bits = parse_ip_prefix("10.0.0.1/8");
  ASSERT_FALSE(host_bits.has_value());
  EXPECT_EQ(host_bits.error(), "'10.0.0.1/8': address bits set beyond the /8 prefix");
  auto too_long = parse_ip_prefix("10.0.0.0/33");
  ASSERT_FALSE(too_long.has_value());
  EXPECT_EQ(too_long.error(), "'10.0.0.0/33': prefix length must be 0..32");
}

TEST(IpPrefix, MatchesAtTheExactBoundaries) {
  // /24: .0 and .255 inside, the neighbours outside.
  EXPECT_TRUE(allows("192.0.2.0/24", v4("192.0.2.0")));
  EXPECT_TRUE(allows("192.0.2.0/24", v4("192.0.2.255")));
  EXPECT_FALSE(allows("192.0.2.0/24", v4("192.0.1.255")));
  EXPECT_FALSE(allows("192.0.2.0/24", v4("192.0.3.0")));
  // A prefix length that ends inside a byte: 10.0.0.0/9 = 10.0.0.0-10.127.255.255.
  EXPECT_TRUE(allows("10.0.0.0/9", v4("10.127.255.255")));
  EXPECT_FALSE(allows("10.0.0.0/9", v4("10.128.0.0")));
  // /31 and /32.
  EXPECT_TRUE(allows("198.51.100.6/31", v4("198.51.100.7")));
  EXPECT_FALSE(allows("198.51.100.6/31", v4("198.51.100.8")));
  EXPECT_TRUE(allows("198.51.100.7", v4("198.51.100.7")));
  EXPECT_FALSE(allows("198.51.100.7", v4("198.51.100.6")));
  // /0: every IPv4 peer, but not IPv6 ones.
  EXPECT_TRUE(allows("0.0.0.0/0", v4("255.255.255.255")));
  EXPECT_FALSE(allows("0.0.0.0/0", v6("2001:db8::1")));
  // IPv6 prefix ending inside a byte: fe80::/10 = fe80:: .. febf:ffff:...
  EXPECT_TRUE(allows("fe80::/10", v6("febf:ffff::1")));
  EXPECT_FALSE(allows("fe80::/10", v6("fec0::1")));
  EXPECT_TRUE(allows("::1", v6("::1")));
  EXPECT_FALSE(allows("::1", v6("::2")));
  EXPECT_FALSE(allows("::1", v4("127.0.0.1")));
  // ::/0 is every address, IPv4 ones included (they are ::ffff:a.b.c.d).
  EXPECT_TRUE(allows("::/0", v4("203.0.113.9")));
}

TEST(IpPrefix, IPv4PeerOnADualStackSocketMatchesIPv4Rules) {
  // An IPv4 peer of an AF_INET6 socket arrives as ::ffff:a.b.c.d.
  EXPECT_TRUE(allows("127.0.0.0/8", v6("::ffff:127.0.0.2")));
  EXPECT_FALSE(allows("127.0.0.0/8", v6("::ffff:128.0.0.1")));
  EXPECT_FALSE(allows("127.0.0.0/8", v6("::127.0.0.2")));  // IPv4-compatible form is not IPv4
}

TEST(IpAllowList, ListOfPrefixes) {
  auto l = IpAllowList::parse("10.1.0.0/16,2001:db8::/48,192.0.2.1");
  ASSERT_TRUE(l.has_value()) << l.error();
  EXPECT_EQ(l->prefixes().size(), 3u);
  EXPECT_TRUE(l->allows(v4("10.1.200.3")));
  EXPECT_TRUE(l->allows(v4("192.0.2.1")));
  EXPECT_TRUE(l->allows(v6("2001:db8:0:ffff::5")));
  EXPECT_FALSE(l->allows(v4("10.2.0.1")));
  EXPECT_FALSE(l->allows(v4("192.0.2.2")));
  EXPECT_FALSE(l->allows(v6("2001:db8:1::5")));
  sockaddr_storage unix_peer{};
  unix_peer.ss_family = AF_UNIX;
  EXPECT_FALSE(l->allows(unix_peer));  // not an IP peer: never allowed
  for (const char* bad : {"", ",", "10.0.0.0/8,", ",10.0.0.0/8", "10.0.0.0/8,,::1", "10.0.0.0/8;::1"}) {
    EXPECT_FALSE(IpAllowList::parse(bad).has_value()) << "'" << bad << "' was accepted";
  }
  auto bad = IpAllowList::parse("10.0.0.0/8,bogus");
  ASSERT_FALSE(bad.has_value());
  EXPECT_EQ(bad.error(), "'bogus': not an IPv4 or IPv6 address");
}

}  // namespace
}  // namespace ecat::transport
