#include "transport/raw_socket_transport.hpp"

#include <gtest/gtest.h>

#include "transport_test_util.hpp"

namespace ecat::transport {
namespace {

using namespace std::chrono_literals;

TEST(RawSocketTransport, UnknownInterfaceIsAnError) {
  EXPECT_FALSE(RawSocketTransport::open("nonexistent-if0").has_value());
  EXPECT_FALSE(RawSocketTransport::open("").has_value());
  EXPECT_FALSE(RawSocketTransport::open("an-interface-name-longer-than-ifnamsiz").has_value());
}

// Two sockets on the loopback interface: one sees the other's frame. (On lo
// the kernel loops every sent frame back as an incoming one, so the
// PACKET_IGNORE_OUTGOING property itself needs a real link or veth pair; the
// end-to-end veth scripts cover it.) Needs CAP_NET_RAW, else skipped.
TEST(RawSocketTransport, LoopbackSeesOthersFramesNotItsOwn) {
  auto a = RawSocketTransport::open("lo", {.promiscuous = false});
  if (!a && a.error() == TransportError::PermissionDenied) GTEST_SKIP() << "needs CAP_NET_RAW";
  ASSERT_TRUE(a.has_value());
  auto b = RawSocketTransport::open("lo", {.promiscuous = false});
  ASSERT_TRUE(b.has_value());
  const auto frame = test::brd_frame(0x42);
  ASSERT_TRUE(a->send(frame).has_value());
  std::uint8_t buf[kMaxFrameSize];
  auto n = b->receive(buf, 1s);
  ASSERT_TRUE(n.has_value());
  ASSERT_GE(*n, frame.size());
  EXPECT_EQ(std::vector<std::uint8_t>(buf, buf + frame.size()), frame);
  EXPECT_TRUE(a->ignores_outgoing());  // kernels >= 4.20
  std::vector<std::uint8_t> ip = frame;
  ip[12] = 0x08;
  ip[13] = 0x00;
  EXPECT_EQ(a->send(ip).error(), TransportError::InvalidFrame);
}

}  // namespace
}  // namespace ecat::transport
