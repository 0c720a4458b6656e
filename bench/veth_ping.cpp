// ecat-bench-ping: the wire round trip as a master sees it, for
// scripts/bench-veth. Sends one EtherCAT frame (BRD of AL status + an LRW of
// LENGTH bytes) every PERIOD µs on a raw socket, waits for it to come back
// and prints the median, p99 and maximum round trip and the cycle jitter.
// Against ecat-slave it measures the emulator; against a kernel echo (tc
// mirred) on the same veth it measures the bare path.
//   ecat-bench-ping IFACE [COUNT=5000] [PERIOD_US=1000] [LENGTH=30]
// An edge program: it sleeps and reads the system clock, the stack does not.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "common/frame_builder.hpp"
#include "esc/registers.hpp"
#include "transport/raw_socket_transport.hpp"

namespace {

using namespace ecat;

Nanoseconds now() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return Nanoseconds{static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec};
}

void sleep_until(Nanoseconds t) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(t.count() / 1'000'000'000);
  ts.tv_nsec = static_cast<long>(t.count() % 1'000'000'000);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) != 0) {
  }
}

double us(Nanoseconds d) { return static_cast<double>(d.count()) / 1e3; }

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: ecat-bench-ping IFACE [COUNT] [PERIOD_US] [LENGTH]\n");
    return 2;
  }
  const std::string iface = argv[1];
  const long count = argc > 2 ? std::atol(argv[2]) : 5000;
  const long period_us = argc > 3 ? std::atol(argv[3]) : 1000;
  const long length = argc > 4 ? std::atol(argv[4]) : 30;
  if (count <= 0 || period_us <= 0 || length <= 0 || length > static_cast<long>(kMaxDatagramData) - 14) {
    std::fprintf(stderr, "ecat-bench-ping: bad arguments\n");
    return 2;
  }
  auto t = transport::RawSocketTransport::open(iface);
  if (!t) {
    std::fprintf(stderr, "ecat-bench-ping: cannot open %s: %s\n", iface.c_str(),
                 std::string(transport::describe(t.error())).c_str());
    return 1;
  }
  std::vector<std::uint8_t> frame(kEthernetHeaderSize + kMaxEthernetPayload);
  std::vector<std::uint8_t> reply(frame.size() + kVlanTagSize);
  const MacAddress source{0x02, 0x00, 0x00, 0x00, 0x00, 0x01};
  FrameBuilder b(frame, kBroadcastMac, source);
  (void)b.append_zeros(Command::Brd, 0, device_address(0, esc::reg::kAlStatus), 2);
  (void)b.append_zeros(Command::Lrw, 1, 0, static_cast<std::uint16_t>(length));
  const auto sent = b.finish();
  const std::size_t index_at = b.ethercat_offset() + kFrameHeaderSize + DatagramView::kIndexOffset;

  std::vector<Nanoseconds> rtt;
  rtt.reserve(static_cast<std::size_t>(count));
  Nanoseconds jitter_max{0};
  long lost = 0;
  const Nanoseconds period{period_us * 1000};
  const Nanoseconds start = now() + period;
  for (long i = 0; i < count; ++i) {
    const Nanoseconds scheduled = start + period * i;
    sleep_until(scheduled);
    const Nanoseconds t0 = now();
    jitter_max = std::max(jitter_max, t0 - scheduled);
    sent[index_at] = static_cast<std::uint8_t>(i);  // tells this frame from a late one
    if (!t->send(sent)) {
      ++lost;
      continue;
    }
    bool back = false;
    while (!back) {
      const Nanoseconds left = scheduled + period - now();
      if (left <= Nanoseconds{0}) break;
      auto n = t->receive(reply, left);
      if (!n) break;
      back = *n >= index_at + 1 && reply[index_at] == static_cast<std::uint8_t>(i);
    }
    if (back) {
      rtt.push_back(now() - t0);
    } else {
      ++lost;
    }
  }
  std::sort(rtt.begin(), rtt.end());
  auto pct = [&](double p) { return rtt.empty() ? Nanoseconds{0} : rtt[static_cast<std::size_t>(p * static_cast<double>(rtt.size() - 1))]; };
  std::printf("frames %ld lost %ld rtt-median-us %.1f rtt-p99-us %.1f rtt-max-us %.1f cycle-jitter-max-us %.1f\n", count,
              lost, us(pct(0.5)), us(pct(0.99)), rtt.empty() ? 0.0 : us(rtt.back()), us(jitter_max));
  return lost == count ? 1 : 0;
}
