// ecat-bench-echo: the bare user-space echo for scripts/bench-veth and
// scripts/bench-rtt. It receives every EtherCAT frame on IFACE (or, with
// --udp, every EtherCAT-in-UDP datagram on ADDR:PORT) through the same
// transport and the same wait as ecat-slave (a blocking wait of at most
// 50 ms, or polling with --busy-poll), sets the source-MAC bit an ESC sets
// (ESC datasheet Section I §3.2) and sends the frame straight back, with no
// emulation at all. The round trip a master sees through it is the floor
// for ecat-slave on the same medium: socket, scheduler and wake-up costs.
//   ecat-bench-echo IFACE [--busy-poll]
//   ecat-bench-echo --udp PORT|ADDR:PORT [--busy-poll]
// (PORT alone: 127.0.0.1 and ::1, as ecat-slave --udp PORT.)
// Runs until SIGINT/SIGTERM. An edge program: it reads no clock.
#include <array>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

#include "common/frame.hpp"
#include "transport/raw_socket_transport.hpp"
#include "transport/udp_transport.hpp"

namespace {

volatile std::sig_atomic_t g_stop = 0;
void on_stop(int) { g_stop = 1; }

// Same longest wait as ecat-slave's live loop (apps/ecat-slave/run_live.cpp).
constexpr ecat::Nanoseconds kMaxWait = std::chrono::milliseconds(50);

std::unique_ptr<ecat::transport::Transport> open_udp(const std::string& where) {
  using namespace ecat::transport;
  const bool port_only = where.find_first_not_of("0123456789") == std::string::npos;
  auto ep = parse_udp_endpoint(port_only ? "127.0.0.1:" + where : where);
  if (!ep) return nullptr;
  auto t = port_only ? UdpTransport::bind_loopback(ep->port) : UdpTransport::bind(*ep);
  if (!t) return nullptr;
  return std::make_unique<UdpTransport>(std::move(*t));
}

std::unique_ptr<ecat::transport::Transport> open_raw(const std::string& iface) {
  auto t = ecat::transport::RawSocketTransport::open(iface);
  if (!t) return nullptr;
  return std::make_unique<ecat::transport::RawSocketTransport>(std::move(*t));
}

}  // namespace

int main(int argc, char** argv) {
  using namespace ecat;
  const bool udp = argc >= 3 && std::strcmp(argv[1], "--udp") == 0;
  const int first = udp ? 2 : 1;  // the interface or the endpoint
  const bool busy_poll = argc == first + 2 && std::strcmp(argv[first + 1], "--busy-poll") == 0;
  if (argc < first + 1 || argc > first + 2 || (argc == first + 2 && !busy_poll) || argv[first][0] == '-') {
    std::fprintf(stderr, "usage: ecat-bench-echo (IFACE | --udp PORT|ADDR:PORT) [--busy-poll]\n");
    return 2;
  }
  const std::string where = argv[first];
  auto t = udp ? open_udp(where) : open_raw(where);
  if (!t) {
    std::fprintf(stderr, "ecat-bench-echo: cannot open %s%s\n", udp ? "UDP " : "", where.c_str());
    return 1;
  }
  struct sigaction sa {};
  sa.sa_handler = on_stop;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);

  std::array<std::uint8_t, kMaxEthernetPayload + kEthernetHeaderSize + kVlanTagSize> buffer{};
  unsigned long echoed = 0;
  const Nanoseconds wait = busy_poll ? Nanoseconds{0} : kMaxWait;
  while (!g_stop) {
    auto n = t->receive(buffer, wait);
    if (!n) continue;
    if (*n <= kMacSize) continue;
    buffer[kMacSize] = static_cast<std::uint8_t>(buffer[kMacSize] | kSourceMacProcessedBit);
    if (t->send(std::span<const std::uint8_t>(buffer.data(), *n))) ++echoed;
  }
  std::fprintf(stderr, "ecat-bench-echo: %lu frames echoed\n", echoed);
  return 0;
}
