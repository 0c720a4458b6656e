// The PDI host on its Unix socket (pdi_host/pdi_host.hpp), on simulated
// time: a firmware attaches and gets HELLO, is answered, a second one is
// refused, a malformed message closes the connection with the ESC running
// on, and when the firmware goes the ESC behaves as silicon with a silent
// µC: the master is still answered and the PDI watchdog expires; the next
// firmware may attach.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "esc/register_bits.hpp"
#include "esc/registers.hpp"
#include "tests/pdi_host/host_bench.hpp"

namespace ecat::test {
namespace {

TEST(PdiHost, SocketIsTheOwnersOnlyAndAFirmwareIsGreetedAndAnswered) {
  HostBench b;
  struct stat st {};
  ASSERT_EQ(::stat(b.path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  const int fd = b.connect_firmware();
  b.host->service(b.p.clock.now());
  EXPECT_TRUE(b.host->attached());
  const Bytes8 hello = HostBench::take(fd, kGreeting);
  ASSERT_EQ(hello.size(), kGreeting);
  EXPECT_EQ(Bytes8(hello.begin(), hello.begin() + 8), (Bytes8{0xC0, 0, 4, 0, 1, 0, 0, 0}));
  HostBench::send(fd, {0x02, 0, 3, 0, 0x00, 0x1F, 0x5A, 0x01, 0, 4, 0, 0x00, 0x1F, 1, 0});
  b.host->service(b.p.clock.now());
  EXPECT_EQ(HostBench::take(fd, 9), (Bytes8{0x82, 0, 0, 0, 0x81, 0, 1, 0, 0x5A}));
  EXPECT_EQ(b.host->stats().messages, 2u);
  // A second firmware is refused (closed at once); the first stays.
  const int second = b.connect_firmware();
  b.host->service(b.p.clock.now());
  EXPECT_EQ(HostBench::take(second, 1).size(), 0u);
  EXPECT_EQ(b.host->stats().refused, 1u);
  EXPECT_TRUE(b.host->attached());
  ::close(second);
  ::close(fd);
}

TEST(PdiHost, MalformedMessageClosesTheConnectionWithTheReasonLogged) {
  HostBench b;
  const int fd = b.connect_firmware();
  b.host->service(b.p.clock.now());
  (void)HostBench::take(fd, kGreeting);
  HostBench::send(fd, {0x04, 0, 0, 0, 0x7E, 0, 0, 0});
  b.host->service(b.p.clock.now());
  EXPECT_FALSE(b.host->attached());
  EXPECT_EQ(HostBench::take(fd, 12).size(), 12u);  // the TIME reply before the bad message
  EXPECT_EQ(HostBench::take(fd, 1).size(), 0u);    // then the end of the connection
  ASSERT_FALSE(b.log.empty());
  EXPECT_EQ(b.log.back(), "pdi-host: firmware disconnected: unknown message type 0x7E");
  EXPECT_EQ(b.host->stats().dropped, 1u);
  ::close(fd);
}

TEST(PdiHost, FirmwareGoneLeavesTheEscRunningItsPdiWatchdogExpiresAndAReconnectWorks) {
  HostBench b;
  ASSERT_TRUE(b.p.master.scan());
  esc::Esc& e = b.p.chain[0].esc();
  const int fd = b.connect_firmware();
  b.host->service(b.p.clock.now());
  (void)HostBench::take(fd, kGreeting);
  // The firmware writes: the PDI watchdog (0x0410, 100 ms by default) is fed.
  HostBench::send(fd, {0x02, 0, 4, 0, 0x30, 0x01, 0x02, 0x00});  // AL status PreOp
  b.host->service(b.p.clock.now());
  (void)HostBench::take(fd, 4);
  b.p.advance(std::chrono::milliseconds(1));
  EXPECT_NE(e.register_u16(esc::reg::kDlStatus) & esc::bits::kDlPdiWatchdogOk, 0);
  ::close(fd);  // the firmware dies
  b.host->service(b.p.clock.now());
  EXPECT_FALSE(b.host->attached());
  EXPECT_EQ(b.log.back(), "pdi-host: firmware disconnected: the firmware closed its socket");
  b.p.advance(std::chrono::milliseconds(150));
  EXPECT_EQ(e.register_u16(esc::reg::kDlStatus) & esc::bits::kDlPdiWatchdogOk, 0);
  // AL status stays as the firmware left it; the master is answered.
  EXPECT_EQ(e.register_u16(esc::reg::kAlStatus), 0x0002);
  auto st = b.p.master.read_al_status(0);
  ASSERT_TRUE(st);
  EXPECT_TRUE(st->is(master::AlState::PreOp));
  // A new firmware attaches and feeds the watchdog again.
  const int again = b.connect_firmware();
  b.host->service(b.p.clock.now());
  EXPECT_EQ(HostBench::take(again, kGreeting).size(), kGreeting);
  HostBench::send(again, {0x02, 0, 3, 0, 0x00, 0x1F, 0x00});
  b.host->service(b.p.clock.now());
  (void)HostBench::take(again, 4);
  b.p.advance(std::chrono::milliseconds(1));
  EXPECT_NE(e.register_u16(esc::reg::kDlStatus) & esc::bits::kDlPdiWatchdogOk, 0);
  EXPECT_EQ(b.host->stats().connections, 2u);
  ::close(again);
}

}  // namespace
}  // namespace ecat::test
