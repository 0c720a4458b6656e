// ecat-bench-echo: the bare user-space echo for scripts/bench-veth. It
// receives every EtherCAT frame on IFACE through the same raw socket
// transport and the same wait as ecat-slave (a blocking wait of at most
// 50 ms, or polling with --busy-poll), sets the source-MAC bit an ESC sets
// (ESC datasheet Section I §3.2) and sends the frame straight back, with no
// emulation at all. The round trip a master sees through it is the floor
// for ecat-slave on the same veth: socket, scheduler and wake-up costs.
//   ecat-bench-echo IFACE [--busy-poll]
// Runs until SIGINT/SIGTERM. An edge program: it reads no clock.
#include <array>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>

#include "common/frame.hpp"
#include "transport/raw_socket_transport.hpp"

namespace {

volatile std::sig_atomic_t g_stop = 0;
void on_stop(int) { g_stop = 1; }

// Same longest wait as ecat-slave's live loop (apps/ecat-slave/run_live.cpp).
constexpr ecat::Nanoseconds kMaxWait = std::chrono::milliseconds(50);

}  // namespace

int main(int argc, char** argv) {
  using namespace ecat;
  const bool busy_poll = argc == 3 && std::strcmp(argv[2], "--busy-poll") == 0;
  if (argc < 2 || argc > 3 || (argc == 3 && !busy_poll)) {
    std::fprintf(stderr, "usage: ecat-bench-echo IFACE [--busy-poll]\n");
    return 2;
  }
  auto t = transport::RawSocketTransport::open(argv[1]);
  if (!t) {
    std::fprintf(stderr, "ecat-bench-echo: cannot open %s: %s\n", argv[1],
                 std::string(transport::describe(t.error())).c_str());
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
