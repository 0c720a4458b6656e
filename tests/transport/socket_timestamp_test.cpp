// Kernel receive timestamps (issue 19): a frame read late still says when it
// arrived, on the steady clock.
#include "transport/socket_timestamp.hpp"

#include <gtest/gtest.h>

#include <thread>

#include "transport/udp_transport.hpp"
#include "transport_test_util.hpp"

namespace ecat::transport {
namespace {

using namespace std::chrono_literals;

TEST(SocketTimestamp, RealtimeStampMovesToTheSteadyClock) {
  // Stamped 3 ms before the realtime reading: 3 ms before the steady one.
  EXPECT_EQ(to_steady(Nanoseconds{1'000'000'000'000}, Nanoseconds{1'000'003'000'000}, Nanoseconds{50'000'000}),
            Nanoseconds{47'000'000});
}

TEST(SocketTimestamp, UdpFrameReadLateCarriesItsArrivalTime) {
  auto slave = UdpTransport::bind({"127.0.0.1", 0});
  ASSERT_TRUE(slave.has_value());
  auto master = UdpTransport::connect({"127.0.0.1", slave->local_port()});
  ASSERT_TRUE(master.has_value());
  // Linux turns receive stamping on for the whole stack through a deferred
  // static key (net_enable_timestamp): a datagram sent right after the first
  // socket asked for stamps may still be stamped only when it is read. Give
  // the kernel a moment, as a long-running slave always has.
  std::this_thread::sleep_for(100ms);
  const SteadyClock clock;
  const Nanoseconds before = clock.now();
  ASSERT_TRUE(master->send(test::brd_frame(1)).has_value());
  const Nanoseconds after = clock.now();
  std::this_thread::sleep_for(20ms);  // the reader is "scheduled late"
  std::uint8_t buf[kMaxFrameSize];
  auto r = slave->receive_stamped(buf, 1s);
  const Nanoseconds read = clock.now();
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->length, test::brd_frame(1).size());
  ASSERT_TRUE(r->arrival.has_value()) << "kernel gave no SO_TIMESTAMPNS stamp";
  // On loopback the stamp is taken inside send(); two clock readings convert
  // it, so allow their spread, far below the 20 ms the reader slept.
  EXPECT_GE(*r->arrival, before - 1ms);
  EXPECT_LE(*r->arrival, after + 1ms);
  EXPECT_GE(read - *r->arrival, 19ms);
}

}  // namespace
}  // namespace ecat::transport
