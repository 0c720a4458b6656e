#include "transport/udp_transport.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "transport_test_util.hpp"

namespace ecat::transport {
namespace {

using namespace std::chrono_literals;

TEST(UdpEndpoint, Parses) {
  auto a = parse_udp_endpoint("127.0.0.1:34980");
  ASSERT_TRUE(a.has_value());
  EXPECT_EQ(a->host, "127.0.0.1");
  EXPECT_EQ(a->port, 0x88A4);
  auto b = parse_udp_endpoint("10.0.0.2");
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ(b->port, kUdpPortEthercat);
  auto c = parse_udp_endpoint("[::1]:4000");
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->host, "::1");
  EXPECT_EQ(c->port, 4000);
  EXPECT_FALSE(parse_udp_endpoint("127.0.0.1:").has_value());
  EXPECT_FALSE(parse_udp_endpoint("127.0.0.1:70000").has_value());
  EXPECT_FALSE(parse_udp_endpoint("127.0.0.1:12x").has_value());
  EXPECT_FALSE(parse_udp_endpoint(":34980").has_value());
  EXPECT_FALSE(parse_udp_endpoint("::1").has_value());
}

TEST(UdpTransport, LoopbackRoundTripStripsAndRestoresEthernetHeader) {
  auto slave = UdpTransport::bind({"127.0.0.1", 0});
  ASSERT_TRUE(slave.has_value());
  const std::uint16_t port = slave->local_port();
  ASSERT_NE(port, 0);
  auto master = UdpTransport::connect({"127.0.0.1", port});
  ASSERT_TRUE(master.has_value());

  // Device side has nobody to answer before the first frame.
  EXPECT_EQ(slave->send(test::brd_frame(1)).error(), TransportError::NotOpen);

  const auto frame = test::brd_frame(0x5A);
  ASSERT_TRUE(master->send(frame).has_value());
  std::uint8_t buf[kMaxFrameSize];
  auto n = slave->receive(buf, 1s);
  ASSERT_TRUE(n.has_value());
  ASSERT_EQ(*n, frame.size());
  // Synthetic Ethernet header, then the UDP payload = EtherCAT header + datagram.
  const std::vector<std::uint8_t> header{0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0, 0, 0, 0, 0, 0, 0x88, 0xA4};
  EXPECT_EQ(std::vector<std::uint8_t>(buf, buf + 14), header);
  EXPECT_EQ(std::vector<std::uint8_t>(buf + 14, buf + *n), std::vector<std::uint8_t>(frame.begin() + 14, frame.end()));

  buf[*n - 2] = 1;  // WKC 1, as one slave would answer
  ASSERT_TRUE(slave->send(ConstBytes(buf, *n)).has_value());
  std::uint8_t reply[kMaxFrameSize];
  auto m = master->receive(reply, 1s);
  ASSERT_TRUE(m.has_value());
  ASSERT_EQ(*m, frame.size());
  EXPECT_EQ(reply[*m - 2], 1);
  EXPECT_EQ(reply[17], 0x5A);  // datagram index survives
}

TEST(UdpTransport, TimeoutAndBadInputAreErrors) {
  auto slave = UdpTransport::bind({"127.0.0.1", 0});
  ASSERT_TRUE(slave.has_value());
  std::uint8_t buf[kMaxFrameSize];
  EXPECT_EQ(slave->receive(buf, 1ms).error(), TransportError::Timeout);
  auto master = UdpTransport::connect({"127.0.0.1", slave->local_port()});
  ASSERT_TRUE(master.has_value());
  std::vector<std::uint8_t> not_ecat = test::brd_frame(1);
  not_ecat[12] = 0x08;
  not_ecat[13] = 0x00;
  EXPECT_EQ(master->send(not_ecat).error(), TransportError::InvalidFrame);
  std::vector<std::uint8_t> huge(kMaxFrameSize + 1, 0);
  EXPECT_EQ(master->send(huge).error(), TransportError::FrameTooLarge);
  EXPECT_FALSE(UdpTransport::connect({"no.such.host.invalid", 1}).has_value());
  // A reply that does not fit the caller's buffer is reported, not truncated silently.
  ASSERT_TRUE(master->send(test::brd_frame(2)).has_value());
  std::uint8_t small[20];
  EXPECT_EQ(slave->receive(small, 1s).error(), TransportError::BufferTooSmall);
}

TEST(UdpTransport, NobodyListeningIsATimeoutNotAnError) {
  std::uint16_t port = 0;
  {
    auto probe = UdpTransport::bind({"127.0.0.1", 0});
    ASSERT_TRUE(probe.has_value());
    port = probe->local_port();
  }  // closed again: nothing listens on `port`
  auto master = UdpTransport::connect({"127.0.0.1", port});
  ASSERT_TRUE(master.has_value());
  std::uint8_t buf[kMaxFrameSize];
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(master->send(test::brd_frame(1)).has_value()) << i;
    auto r = master->receive(buf, 20ms);
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error(), TransportError::Timeout) << i;
  }
}

// The UDP payload of test::brd_frame: EtherCAT header (length 14, type 1) + BRD.
std::vector<std::uint8_t> brd_payload(std::uint8_t idx) {
  const auto f = test::brd_frame(idx);
  return std::vector<std::uint8_t>(f.begin() + kEthernetHeaderSize, f.end());
}

// A plain UDP socket that sends exactly the bytes it is given, as a foreign
// master (or an attacker) would.
class RawUdpPeer {
 public:
  explicit RawUdpPeer(int family = AF_INET) : family_(family), fd_(::socket(family, SOCK_DGRAM | SOCK_CLOEXEC, 0)) {}
  ~RawUdpPeer() {
    if (fd_ >= 0) ::close(fd_);
  }
  bool send_to(std::uint16_t port, const std::vector<std::uint8_t>& bytes) const {
    ssize_t n = -1;
    if (family_ == AF_INET) {
      sockaddr_in a{};
      a.sin_family = AF_INET;
      a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
      a.sin_port = htons(port);
      n = ::sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&a), sizeof a);
    } else {
      sockaddr_in6 a{};
      a.sin6_family = AF_INET6;
      a.sin6_addr = in6addr_loopback;
      a.sin6_port = htons(port);
      n = ::sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&a), sizeof a);
    }
    return n == static_cast<ssize_t>(bytes.size());
  }
  // Whatever came back within `ms`; empty when nothing did.
  std::vector<std::uint8_t> reply(int ms) const {
    timeval tv{0, ms * 1000};
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    std::vector<std::uint8_t> buf(2048);
    const ssize_t n = ::recv(fd_, buf.data(), buf.size(), 0);
    buf.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
    return buf;
  }
  bool ok() const { return fd_ >= 0; }

 private:
  int family_;
  int fd_;
};

TEST(UdpPayload, LengthMustEqualTheEtherCatLength) {
  const auto good = brd_payload(1);  // header 0x100E: 14 bytes follow, type 1
  EXPECT_TRUE(udp_payload_length_consistent(good));
  auto longer = good;
  longer.push_back(0);  // one byte after the frame (e.g. Ethernet-style padding)
  EXPECT_FALSE(udp_payload_length_consistent(longer));
  auto shorter = good;
  shorter.pop_back();  // the header promises one byte more than the datagram holds
  EXPECT_FALSE(udp_payload_length_consistent(shorter));
  // Only bits 10:0 are the length; the type bits 15:12 and reserved bit 11 are not.
  auto type_bits = good;
  type_bits[1] = 0xF8;  // header 0xF80E: still 14 bytes
  EXPECT_TRUE(udp_payload_length_consistent(type_bits));
  EXPECT_FALSE(udp_payload_length_consistent(std::vector<std::uint8_t>{}));
  EXPECT_FALSE(udp_payload_length_consistent(std::vector<std::uint8_t>{0x00}));
  EXPECT_TRUE(udp_payload_length_consistent(std::vector<std::uint8_t>{0x00, 0x10}));  // length 0, header only
  // The largest: 2047 bytes after the header.
  std::vector<std::uint8_t> max(2 + 2047, 0);
  max[0] = 0xFF;
  max[1] = 0x17;
  EXPECT_TRUE(udp_payload_length_consistent(max));
}

TEST(UdpTransport, MasterSendLeavesEthernetPaddingOut) {
  auto slave = UdpTransport::bind({"127.0.0.1", 0});
  ASSERT_TRUE(slave.has_value());
  auto master = UdpTransport::connect({"127.0.0.1", slave->local_port()});
  ASSERT_TRUE(master.has_value());
  auto padded = test::brd_frame(3);
  padded.resize(kMinEthernetFrame, 0);  // as frame_builder sends it
  ASSERT_TRUE(master->send(padded).has_value());
  std::uint8_t buf[kMaxFrameSize];
  auto n = slave->receive(buf, 1s);
  ASSERT_TRUE(n.has_value()) << describe(n.error());
  EXPECT_EQ(*n, test::brd_frame(3).size());  // 14 + 16: no padding crossed the wire
  EXPECT_EQ(slave->stats().length_mismatch, 0u);
}

TEST(UdpTransport, LengthMismatchIsDroppedUnansweredAndCounted) {
  auto slave = UdpTransport::bind({"127.0.0.1", 0});
  ASSERT_TRUE(slave.has_value());
  RawUdpPeer peer;
  ASSERT_TRUE(peer.ok());
  std::uint8_t buf[kMaxFrameSize];
  auto longer = brd_payload(1);
  longer.push_back(0xEE);
  auto shorter = brd_payload(2);
  shorter.pop_back();
  const std::vector<std::vector<std::uint8_t>> bad{longer, shorter, {0x0E}, {}};
  for (std::size_t i = 0; i < bad.size(); ++i) {
    ASSERT_TRUE(peer.send_to(slave->local_port(), bad[i]));
    auto r = slave->receive(buf, 1s);
    ASSERT_FALSE(r.has_value()) << i;
    EXPECT_EQ(r.error(), TransportError::Dropped) << i;
    EXPECT_EQ(slave->stats().length_mismatch, i + 1);
    // Nobody to answer: the dropped datagram made no peer.
    EXPECT_EQ(slave->send(test::brd_frame(1)).error(), TransportError::NotOpen) << i;
  }
  EXPECT_TRUE(peer.reply(20).empty());
  EXPECT_EQ(slave->stats().datagrams_accepted, 0u);
  // A consistent one after them is served.
  ASSERT_TRUE(peer.send_to(slave->local_port(), brd_payload(9)));
  auto ok = slave->receive(buf, 1s);
  ASSERT_TRUE(ok.has_value());
  EXPECT_EQ(*ok, 30u);
  EXPECT_EQ(slave->stats().datagrams_accepted, 1u);
  EXPECT_EQ(slave->stats().length_mismatch, 4u);
}

TEST(UdpTransport, SourcesOutsideTheAllowListAreDroppedUnansweredAndCounted) {
  auto slave = UdpTransport::bind({"127.0.0.1", 0});
  ASSERT_TRUE(slave.has_value());
  auto others = IpAllowList::parse("10.0.0.0/8,::1");
  ASSERT_TRUE(others.has_value());
  slave->set_allow_list(std::move(*others));
  RawUdpPeer peer;
  std::uint8_t buf[kMaxFrameSize];
  ASSERT_TRUE(peer.send_to(slave->local_port(), brd_payload(1)));
  auto r = slave->receive(buf, 1s);
  ASSERT_FALSE(r.has_value());
  EXPECT_EQ(r.error(), TransportError::Dropped);
  EXPECT_EQ(slave->stats().refused_source, 1u);
  EXPECT_EQ(slave->stats().length_mismatch, 0u);
  EXPECT_EQ(slave->send(test::brd_frame(1)).error(), TransportError::NotOpen);
  EXPECT_TRUE(peer.reply(20).empty());
  // The source is checked first: a refused peer's malformed datagram counts as refused only.
  ASSERT_TRUE(peer.send_to(slave->local_port(), {0x01}));
  EXPECT_EQ(slave->receive(buf, 1s).error(), TransportError::Dropped);
  EXPECT_EQ(slave->stats().refused_source, 2u);
  EXPECT_EQ(slave->stats().length_mismatch, 0u);

  auto loopback = IpAllowList::parse("127.0.0.1");
  ASSERT_TRUE(loopback.has_value());
  slave->set_allow_list(std::move(*loopback));
  ASSERT_TRUE(peer.send_to(slave->local_port(), brd_payload(2)));
  auto n = slave->receive(buf, 1s);
  ASSERT_TRUE(n.has_value());
  ASSERT_TRUE(slave->send(ConstBytes(buf, *n)).has_value());
  EXPECT_EQ(peer.reply(1000), brd_payload(2));
}

TEST(UdpTransport, ReplyNeverLongerThanTheRequestAndOnlyOne) {
  auto slave = UdpTransport::bind({"127.0.0.1", 0});
  ASSERT_TRUE(slave.has_value());
  RawUdpPeer peer;
  ASSERT_TRUE(peer.send_to(slave->local_port(), brd_payload(4)));  // 16-byte request
  std::uint8_t buf[kMaxFrameSize];
  auto n = slave->receive(buf, 1s);
  ASSERT_TRUE(n.has_value());
  ASSERT_EQ(*n, 30u);
  // A reply of 17 bytes (EtherCAT length one more) is refused and not sent.
  std::vector<std::uint8_t> bigger(buf, buf + *n);
  bigger[14] = 0x0F;
  bigger.push_back(0);
  EXPECT_EQ(slave->send(bigger).error(), TransportError::FrameTooLarge);
  EXPECT_EQ(slave->stats().replies_refused, 1u);
  EXPECT_TRUE(peer.reply(20).empty());
  // The same size goes out, once.
  ASSERT_TRUE(slave->send(ConstBytes(buf, *n)).has_value());
  EXPECT_EQ(peer.reply(1000).size(), 16u);
  EXPECT_EQ(slave->send(ConstBytes(buf, *n)).error(), TransportError::NotOpen);
  EXPECT_EQ(slave->stats().replies_refused, 2u);
  EXPECT_TRUE(peer.reply(20).empty());
}

TEST(UdpTransport, LoopbackBindServesIpv4AndIpv6LoopbackOnly) {
  auto slave = UdpTransport::bind_loopback(0);
  ASSERT_TRUE(slave.has_value());
  EXPECT_TRUE(slave->loopback_only());
  const std::uint16_t port = slave->local_port();
  ASSERT_NE(port, 0);
  std::uint8_t buf[kMaxFrameSize];
  RawUdpPeer p4(AF_INET);
  ASSERT_TRUE(p4.send_to(port, brd_payload(5)));
  auto n = slave->receive(buf, 1s);
  ASSERT_TRUE(n.has_value());
  ASSERT_TRUE(slave->send(ConstBytes(buf, *n)).has_value());
  EXPECT_EQ(p4.reply(1000), brd_payload(5));
  if (slave->socket_count() < 2) GTEST_SKIP() << "no IPv6 loopback on this host";
  RawUdpPeer p6(AF_INET6);
  ASSERT_TRUE(p6.send_to(port, brd_payload(6)));
  auto m = slave->receive(buf, 1s);
  ASSERT_TRUE(m.has_value());
  ASSERT_TRUE(slave->send(ConstBytes(buf, *m)).has_value());
  EXPECT_EQ(p6.reply(1000), brd_payload(6));  // answered on the socket it came in on

  auto wide = UdpTransport::bind({"0.0.0.0", 0});
  ASSERT_TRUE(wide.has_value());
  EXPECT_FALSE(wide->loopback_only());
  auto one = UdpTransport::bind({"127.0.0.2", 0});
  ASSERT_TRUE(one.has_value());
  EXPECT_TRUE(one->loopback_only());
}

}  // namespace
}  // namespace ecat::transport
