// --eoe-tap: frames both ways between the EoE server and a Linux TAP.
// Skips where /dev/net/tun is missing or the process may not create a TAP.
#include "slave/eoe_tap.hpp"

#include <arpa/inet.h>
#include <linux/if_packet.h>
#include <net/ethernet.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

namespace ecat::slave {
namespace {

using Frame = std::vector<std::uint8_t>;
constexpr std::uint16_t kTestEtherType = 0x88B5;  // IEEE 802 local experimental

Frame test_frame(std::uint8_t tag) {
  Frame f{0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x02, 0xAA, 0xBB, 0xCC, 0xDD, tag, 0x88, 0xB5};
  for (int i = 0; i < 46; ++i) f.push_back(static_cast<std::uint8_t>(tag + i));
  return f;
}

struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

TEST(EoeTap, FramesBothWaysThroughTheHostInterface) {
  if (!std::filesystem::exists("/dev/net/tun")) GTEST_SKIP() << "no /dev/net/tun";
  const std::string name = "ecteoe" + std::to_string(::getpid() % 100000);
  coe::EoeServer server;
  auto tap = EoeTap::open(name, server);
  if (!tap) GTEST_SKIP() << tap.error();
  // No IPv6 chatter on the interface, then up.
  { std::ofstream("/proc/sys/net/ipv6/conf/" + name + "/disable_ipv6") << "1\n"; }
  Fd ctl{::socket(AF_INET, SOCK_DGRAM, 0)};
  ifreq ifr{};
  std::strncpy(ifr.ifr_name, name.c_str(), IFNAMSIZ - 1);
  ASSERT_EQ(::ioctl(ctl.fd, SIOCGIFFLAGS, &ifr), 0);
  ifr.ifr_flags = static_cast<short>(ifr.ifr_flags | IFF_UP);
  ASSERT_EQ(::ioctl(ctl.fd, SIOCSIFFLAGS, &ifr), 0);
  const int index = static_cast<int>(::if_nametoindex(name.c_str()));
  ASSERT_GT(index, 0);
  Fd pkt{::socket(AF_PACKET, SOCK_RAW, htons(kTestEtherType))};
  if (pkt.fd < 0) GTEST_SKIP() << "no packet socket: " << std::strerror(errno);
  sockaddr_ll ll{};
  ll.sll_family = AF_PACKET;
  ll.sll_protocol = htons(kTestEtherType);
  ll.sll_ifindex = index;
  ASSERT_EQ(::bind(pkt.fd, reinterpret_cast<sockaddr*>(&ll), sizeof ll), 0);

  // Master -> host: the frame arrives on the interface as sent.
  const Frame down = test_frame(0x10);
  (*tap)->receive(down);
  EXPECT_EQ((*tap)->stats().to_host, 1u);
  pollfd p{pkt.fd, POLLIN, 0};
  ASSERT_EQ(::poll(&p, 1, 2000), 1) << "nothing arrived on " << name;
  Frame got(2048);
  const ssize_t n = ::recv(pkt.fd, got.data(), got.size(), 0);
  ASSERT_EQ(n, static_cast<ssize_t>(down.size()));
  got.resize(static_cast<std::size_t>(n));
  EXPECT_EQ(got, down);

  // Host -> master: a frame sent out of the interface is queued for the
  // master and comes out as one EoE fragment (frame number 1, 2 blocks).
  const Frame up = test_frame(0x40);
  ASSERT_EQ(::sendto(pkt.fd, up.data(), up.size(), 0, reinterpret_cast<sockaddr*>(&ll), sizeof ll),
            static_cast<ssize_t>(up.size()));
  bool found = false;
  std::array<std::uint8_t, 1600> out{};
  for (int tries = 0; tries < 200 && !found; ++tries) {
    (*tap)->service();
    while (const std::size_t m = server.next_output(out)) {
      const Frame frame(out.begin() + 4, out.begin() + static_cast<std::ptrdiff_t>(m));
      if (frame == up) {
        found = true;
        EXPECT_EQ(out[0], 0x00);
        EXPECT_EQ(out[1], 0x01);  // last fragment
      }
    }
    if (!found) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_TRUE(found) << "the host's frame did not reach the EoE server";
  EXPECT_GE((*tap)->stats().from_host, 1u);
}

TEST(EoeTap, BadNameIsAClearError) {
  coe::EoeServer server;
  auto tap = EoeTap::open(std::string(40, 'x'), server);
  ASSERT_FALSE(tap);
  EXPECT_NE(tap.error().find("interface name"), std::string::npos) << tap.error();
}

}  // namespace
}  // namespace ecat::slave
