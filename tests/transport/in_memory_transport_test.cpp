#include "transport/in_memory_transport.hpp"

#include <gtest/gtest.h>

#include "transport_test_util.hpp"

namespace ecat::transport {
namespace {

TEST(InMemoryTransport, ProcessesInPlaceAndQueues) {
  int calls = 0;
  InMemoryTransport t([&](Bytes f) {
    ++calls;
    f[f.size() - 2] = 3;  // WKC
  });
  t.record_sent(true);
  ASSERT_TRUE(t.send(test::brd_frame(1)).has_value());
  ASSERT_TRUE(t.send(test::brd_frame(2)).has_value());
  EXPECT_EQ(calls, 2);
  EXPECT_EQ(t.pending(), 2u);
  ASSERT_EQ(t.sent_frames().size(), 2u);
  EXPECT_EQ(t.sent_frames()[0], test::brd_frame(1));  // recorded before processing
  std::uint8_t buf[kMaxFrameSize];
  auto n = t.receive(buf, Nanoseconds{0});
  ASSERT_TRUE(n.has_value());
  EXPECT_EQ(buf[17], 1);
  EXPECT_EQ(buf[*n - 2], 3);
  ASSERT_TRUE(t.receive(buf, Nanoseconds{0}).has_value());
  EXPECT_EQ(t.receive(buf, Nanoseconds{1'000'000}).error(), TransportError::Timeout);
}

TEST(InMemoryTransport, DropNextLosesRepliesButStillProcesses) {
  int calls = 0;
  InMemoryTransport t([&](Bytes) { ++calls; });
  t.drop_next(1);
  ASSERT_TRUE(t.send(test::brd_frame(1)).has_value());
  ASSERT_TRUE(t.send(test::brd_frame(2)).has_value());
  EXPECT_EQ(calls, 2);
  std::uint8_t buf[kMaxFrameSize];
  ASSERT_TRUE(t.receive(buf, Nanoseconds{0}).has_value());
  EXPECT_EQ(buf[17], 2);
  std::uint8_t small[8];
  ASSERT_TRUE(t.send(test::brd_frame(3)).has_value());
  EXPECT_EQ(t.receive(small, Nanoseconds{0}).error(), TransportError::BufferTooSmall);
}

}  // namespace
}  // namespace ecat::transport
