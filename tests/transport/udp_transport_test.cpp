#include "transport/udp_transport.hpp"

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

}  // namespace
}  // namespace ecat::transport
