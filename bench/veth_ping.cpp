// ecat-bench-ping: the wire round trip as a master sees it, for
// scripts/bench-veth and scripts/bench-rtt. Sends one EtherCAT frame (BRD of
// AL status + an LRW of LENGTH bytes) every PERIOD µs, waits for it to come
// back and prints the median, p99 and maximum round trip and the cycle
// jitter (how late the pinger woke for its sends). A frame not back within
// one period of its send is lost. On one of three media (issue 30 item 4):
//   IFACE                a raw socket on a network interface (a veth end):
//                        ecat-slave --iface, ecat-bench-echo or a kernel echo
//                        (tc mirred) on the other end;
//   --udp ADDR[:PORT]    EtherCAT-in-UDP (ETG.1000.4 §5.3) to ecat-slave --udp
//                        or ecat-bench-echo --udp;
//   --in-process N       no wire: the frame is handed to N generic servos in
//                        this process (slave::Chain::pass_frame through
//                        transport::InMemoryTransport, as ecat-master
//                        --in-process does; the firmware runs after the
//                        frame is back, off the round trip, as ecat-slave
//                        runs it after the send); N = 0 is the in-process
//                        echo (the same transport, the source-MAC bit set
//                        and nothing else).
//   ecat-bench-ping (IFACE | --udp ADDR[:PORT] | --in-process N)
//                   [COUNT=5000] [PERIOD_US=1000] [LENGTH=30] [--raw FILE]
// --raw FILE writes every round trip in ns, one a line, in the order sent
// (scripts/bench-rtt pools the runs of a case for its median and p99).
// An edge program: it sleeps and reads the system clock, the stack does not.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "common/clock.hpp"
#include "common/frame_builder.hpp"
#include "esc/registers.hpp"
#include "esi/device_loader.hpp"
#include "slave/chain.hpp"
#include "transport/in_memory_transport.hpp"
#include "transport/raw_socket_transport.hpp"
#include "transport/udp_transport.hpp"

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

// Most slaves --in-process builds (ecat-slave's own --count has no lower cap;
// a thousand is the largest case, ten thousand leaves room).
constexpr long kMaxInProcessSlaves = 10'000;

enum class Medium : std::uint8_t { Raw, Udp, InProcess };

struct Arguments {
  Medium medium = Medium::Raw;
  std::string where;  // interface or UDP endpoint
  long slaves = 0;    // --in-process
  long count = 5000;
  long period_us = 1000;
  long length = 30;
  std::string raw_file;
};

bool parse_count(const char* text, long& out) {
  char* end = nullptr;
  out = std::strtol(text, &end, 10);
  return end != text && *end == '\0';
}

bool parse(int argc, char** argv, Arguments& a) {
  std::vector<const char*> positional;
  bool have_medium = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--udp" && has_value && !have_medium) {
      a.medium = Medium::Udp;
      a.where = argv[++i];
      have_medium = true;
    } else if (arg == "--in-process" && has_value && !have_medium) {
      a.medium = Medium::InProcess;
      if (!parse_count(argv[++i], a.slaves) || a.slaves < 0 || a.slaves > kMaxInProcessSlaves) return false;
      have_medium = true;
    } else if (arg == "--raw" && has_value) {
      a.raw_file = argv[++i];
    } else if (arg.starts_with("--")) {
      return false;
    } else if (!have_medium) {
      a.medium = Medium::Raw;
      a.where = arg;
      have_medium = true;
    } else {
      positional.push_back(argv[i]);
    }
  }
  if (!have_medium || positional.size() > 3) return false;
  long* fields[] = {&a.count, &a.period_us, &a.length};
  for (std::size_t i = 0; i < positional.size(); ++i) {
    if (!parse_count(positional[i], *fields[i])) return false;
  }
  return a.count > 0 && a.period_us > 0 && a.length > 0 &&
         a.length <= static_cast<long>(kMaxDatagramData) - 14;
}

// The in-process medium: a line of generic servos (or none: the echo) behind
// an InMemoryTransport, on the steady clock the round trip is timed with.
struct InProcess {
  SteadyClock clock;
  std::unique_ptr<slave::Chain> chain;
  std::unique_ptr<transport::InMemoryTransport> transport;
};

std::unique_ptr<InProcess> open_in_process(long slaves) {
  auto p = std::make_unique<InProcess>();
  if (slaves > 0) {
    auto device = esi::load_default_device();
    if (!device) {
      std::fprintf(stderr, "ecat-bench-ping: %s\n", device.error().to_string().c_str());
      return nullptr;
    }
    // One description for all, as ecat-slave --count shares nothing but
    // costs the same per frame.
    auto shared = std::make_shared<const od::DeviceDescription>(std::move(*device));
    p->chain = std::make_unique<slave::Chain>(p->clock);
    for (long i = 0; i < slaves; ++i) {
      slave::SlaveOptions o;
      o.name = "slave-" + std::to_string(i + 1);
      if (auto ok = p->chain->add(shared, o); !ok) {
        std::fprintf(stderr, "ecat-bench-ping: slave %ld: %s\n", i + 1, ok.error().c_str());
        return nullptr;
      }
    }
    (void)p->chain->poll(p->clock.now());
  }
  slave::Chain* chain = p->chain.get();
  const SteadyClock* clock = &p->clock;
  p->transport = std::make_unique<transport::InMemoryTransport>([chain, clock](Bytes frame) {
    if (chain != nullptr) {
      (void)chain->pass_frame(frame, clock->now());
    } else if (frame.size() > kMacSize) {
      frame[kMacSize] = static_cast<std::uint8_t>(frame[kMacSize] | kSourceMacProcessedBit);
    }
  });
  return p;
}

}  // namespace

int main(int argc, char** argv) {
  Arguments a;
  if (!parse(argc, argv, a)) {
    std::fprintf(stderr,
                 "usage: ecat-bench-ping (IFACE | --udp ADDR[:PORT] | --in-process N) [COUNT] [PERIOD_US] [LENGTH] "
                 "[--raw FILE]\n");
    return 2;
  }
  std::unique_ptr<transport::Transport> owned;
  std::unique_ptr<InProcess> in_process;
  if (a.medium == Medium::Raw) {
    auto t = transport::RawSocketTransport::open(a.where);
    if (!t) {
      std::fprintf(stderr, "ecat-bench-ping: cannot open %s: %s\n", a.where.c_str(),
                   std::string(transport::describe(t.error())).c_str());
      return 1;
    }
    owned = std::make_unique<transport::RawSocketTransport>(std::move(*t));
  } else if (a.medium == Medium::Udp) {
    auto ep = transport::parse_udp_endpoint(a.where);
    auto t = ep ? transport::UdpTransport::connect(*ep)
                : Expected<transport::UdpTransport, transport::TransportError>(fail(ep.error()));
    if (!t) {
      std::fprintf(stderr, "ecat-bench-ping: --udp %s: %s\n", a.where.c_str(),
                   std::string(transport::describe(t.error())).c_str());
      return 1;
    }
    owned = std::make_unique<transport::UdpTransport>(std::move(*t));
  } else {
    in_process = open_in_process(a.slaves);
    if (!in_process) return 1;
  }
  transport::Transport& t = in_process ? *in_process->transport : *owned;
  slave::Chain* chain = in_process ? in_process->chain.get() : nullptr;

  std::vector<std::uint8_t> frame(kEthernetHeaderSize + kMaxEthernetPayload);
  std::vector<std::uint8_t> reply(frame.size() + kVlanTagSize);
  const MacAddress source{0x02, 0x00, 0x00, 0x00, 0x00, 0x01};
  FrameBuilder b(frame, kBroadcastMac, source);
  (void)b.append_zeros(Command::Brd, 0, device_address(0, esc::reg::kAlStatus), 2);
  (void)b.append_zeros(Command::Lrw, 1, 0, static_cast<std::uint16_t>(a.length));
  const auto sent = b.finish();
  const std::size_t index_at = b.ethercat_offset() + kFrameHeaderSize + DatagramView::kIndexOffset;

  std::vector<Nanoseconds> rtt;
  rtt.reserve(static_cast<std::size_t>(a.count));
  Nanoseconds jitter_max{0};
  long lost = 0;
  const Nanoseconds period{a.period_us * 1000};
  const Nanoseconds start = now() + period;
  for (long i = 0; i < a.count; ++i) {
    const Nanoseconds scheduled = start + period * i;
    sleep_until(scheduled);
    const Nanoseconds t0 = now();
    jitter_max = std::max(jitter_max, t0 - scheduled);
    sent[index_at] = static_cast<std::uint8_t>(i);  // tells this frame from a late one
    if (!t.send(sent)) {
      ++lost;
      continue;
    }
    // A frame has one period from its send to come back: a pinger woken
    // late (a loaded host) still measures the round trip of what it sent.
    bool back = false;
    while (!back) {
      const Nanoseconds left = t0 + period - now();
      if (left <= Nanoseconds{0}) break;
      auto n = t.receive(reply, left);
      if (!n) {
        if (n.error() == transport::TransportError::Timeout && !in_process) continue;
        break;
      }
      back = *n >= index_at + 1 && reply[index_at] == static_cast<std::uint8_t>(i);
    }
    if (back) {
      rtt.push_back(now() - t0);
    } else {
      ++lost;
    }
    if (chain != nullptr) {
      // What ecat-slave does after the send: the firmware, then the timers.
      chain->run_firmware(now());
      (void)chain->poll(now());
    }
  }
  if (!a.raw_file.empty()) {
    std::FILE* f = std::fopen(a.raw_file.c_str(), "w");
    if (f == nullptr) {
      std::fprintf(stderr, "ecat-bench-ping: %s: cannot write\n", a.raw_file.c_str());
      return 1;
    }
    for (Nanoseconds d : rtt) std::fprintf(f, "%lld\n", static_cast<long long>(d.count()));
    if (std::fclose(f) != 0) {
      std::fprintf(stderr, "ecat-bench-ping: %s: write failed\n", a.raw_file.c_str());
      return 1;
    }
  }
  std::sort(rtt.begin(), rtt.end());
  auto pct = [&](double p) { return rtt.empty() ? Nanoseconds{0} : rtt[static_cast<std::size_t>(p * static_cast<double>(rtt.size() - 1))]; };
  std::printf("frames %ld lost %ld rtt-median-us %.1f rtt-p99-us %.1f rtt-max-us %.1f cycle-jitter-max-us %.1f\n", a.count,
              lost, us(pct(0.5)), us(pct(0.99)), rtt.empty() ? 0.0 : us(rtt.back()), us(jitter_max));
  return lost == a.count ? 1 : 0;
}
