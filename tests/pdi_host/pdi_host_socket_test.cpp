// The PDI host on its Unix socket (pdi_host/pdi_host.hpp), on simulated
// time: a firmware attaches and gets HELLO, is answered, a second one is
// refused, a malformed message closes the connection with the ESC running
// on, and when the firmware goes the ESC behaves as silicon with a silent
// µC: the master is still answered and the PDI watchdog expires; the next
// firmware may attach.
#include <gtest/gtest.h>

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "esc/register_bits.hpp"
#include "esc/registers.hpp"
#include "pdi_host/pdi_host.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

using Bytes8 = std::vector<std::uint8_t>;

struct HostBench {
  HostBench() {
    char templ[] = "/tmp/pdi_host_test.XXXXXX";
    dir = ::mkdtemp(templ);
    path = dir + "/pdi.sock";
    auto d = esi::load_default_device();
    if (!d) throw std::runtime_error("default device");
    slave::SlaveOptions o;
    o.external_firmware = true;
    p.add(*d, o);
    auto h = pdi_host::PdiHost::open(path, p.chain[0].esc(), pdi_host::PdiChip::Direct, p.clock,
                                     [this](const std::string& line) { log.push_back(line); });
    if (!h) throw std::runtime_error(h.error());
    host = std::move(*h);
  }
  ~HostBench() {
    host.reset();
    ::rmdir(dir.c_str());
  }
  int connect_firmware() {
    const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    std::snprintf(a.sun_path, sizeof(a.sun_path), "%s", path.c_str());
    EXPECT_EQ(::connect(fd, reinterpret_cast<const sockaddr*>(&a), sizeof(a)), 0);
    timeval tv{1, 0};
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
    return fd;
  }
  // Reads exactly n bytes (the host has been serviced before).
  static Bytes8 take(int fd, std::size_t n) {
    Bytes8 b(n);
    std::size_t got = 0;
    while (got < n) {
      const ssize_t r = ::recv(fd, b.data() + got, n - got, 0);
      if (r <= 0) break;
      got += static_cast<std::size_t>(r);
    }
    b.resize(got);
    return b;
  }
  static void send(int fd, const Bytes8& b) { ASSERT_EQ(::send(fd, b.data(), b.size(), 0), static_cast<ssize_t>(b.size())); }

  std::string dir;
  std::string path;
  InProcess p;
  std::vector<std::string> log;
  std::unique_ptr<pdi_host::PdiHost> host;
};

constexpr std::size_t kGreeting = 8 + 24;  // HELLO + the lines

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
