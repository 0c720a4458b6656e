// ecat-bench-pdi: what a firmware pays for the PDI host (issue 28 item 4),
// for scripts/bench-pdi. Attached as the firmware of `ecat-slave --udp PORT
// --pdi-host SOCKET` (direct PDI), it times, through libecat_pdi:
//   - one PDI access, round trip as the firmware sees it (READ 2 bytes of AL
//     status, READ 64 bytes of process RAM, WRITE 2 bytes, TIME);
//   - the latency from a SYNC0 pulse to the firmware seeing its interrupt
//     (ecat_pdi_wait_irq returning with the SYNC0 bit): a master (the
//     project's, over UDP, in this process) starts SYNC0 with CYCLE_US, and
//     each pulse's time is the sync unit's start time 0x0990 + k x cycle in
//     the ESC's system time, turned into CLOCK_MONOTONIC by reading 0x0910
//     through the PDI (the read with the shortest round trip of 200; half
//     of it bounds the error, printed). Split into the host's part (pulse ->
//     the host sends the lines, whose time stamp is the host's
//     CLOCK_MONOTONIC) and the socket's (sent -> seen, no calibration).
//     A pulse told only together with a later one (the host or the firmware
//     a cycle late) counts in the first row with its own latency; the two
//     split rows are the pulses told on their own.
// Prints one table: median, p99, max in µs.
//   ecat-bench-pdi SOCKET HOST:PORT [ACCESSES=20000] [PULSES=5000] [CYCLE_US=1000]
// An edge program: it reads the system clock, the stack does not.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <string>
#include <vector>

#include "common/clock.hpp"
#include "common/le.hpp"
#include "ecat_pdi.h"
#include "master/master.hpp"
#include "master/registers.hpp"
#include "transport/udp_transport.hpp"

namespace {

using namespace ecat;

constexpr std::uint16_t kAlStatus = 0x0130;
constexpr std::uint16_t kAlEventMask = 0x0204;
constexpr std::uint16_t kRamRead = 0x1000;   // process RAM
constexpr std::uint16_t kRamWrite = 0x2F00;  // process RAM, outside the SMs of the default device
constexpr std::uint16_t kSystemTime = master::reg::kDcSystemTime;
constexpr std::uint16_t kStartTime = 0x0990;  // start time cyclic operation / next SYNC0 pulse
constexpr int kCalibrationReads = 200;
constexpr int kWarmUp = 1000;

std::int64_t mono_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

struct Summary {
  double median_us = 0, p99_us = 0, max_us = 0, mean_us = 0;
  std::size_t n = 0;
};

Summary summarise(std::vector<std::int64_t> v) {
  Summary s;
  s.n = v.size();
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  double sum = 0;
  for (std::int64_t x : v) sum += static_cast<double>(x);
  s.median_us = static_cast<double>(v[v.size() / 2]) / 1e3;
  s.p99_us = static_cast<double>(v[std::min(v.size() - 1, v.size() * 99 / 100)]) / 1e3;
  s.max_us = static_cast<double>(v.back()) / 1e3;
  s.mean_us = sum / static_cast<double>(v.size()) / 1e3;
  return s;
}

void row(const char* what, const Summary& s) {
  std::printf("| %-44s | %7zu | %8.1f | %8.1f | %9.1f | %8.1f |\n", what, s.n, s.median_us, s.p99_us, s.max_us,
              s.mean_us);
}

// Times `count` calls of `access` (after kWarmUp untimed ones); false when one failed.
bool time_access(const std::function<int()>& access, long count, std::vector<std::int64_t>& out) {
  for (int i = 0; i < kWarmUp; ++i) {
    if (access() != 0) return false;
  }
  out.reserve(static_cast<std::size_t>(count));
  for (long i = 0; i < count; ++i) {
    const std::int64_t t0 = mono_ns();
    if (access() != 0) return false;
    out.push_back(mono_ns() - t0);
  }
  return true;
}

int pdi_failed(ecat_pdi* pdi, const char* what) {
  std::fprintf(stderr, "ecat-bench-pdi: %s: %s\n", what, ecat_pdi_error(pdi));
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: ecat-bench-pdi SOCKET HOST:PORT [ACCESSES] [PULSES] [CYCLE_US]\n");
    return 2;
  }
  const long accesses = argc > 3 ? std::atol(argv[3]) : 20000;
  const long pulses = argc > 4 ? std::atol(argv[4]) : 5000;
  const long cycle_us = argc > 5 ? std::atol(argv[5]) : 1000;
  if (accesses <= 0 || pulses <= 0 || cycle_us <= 0 || cycle_us > 1'000'000) {
    std::fprintf(stderr, "ecat-bench-pdi: bad arguments\n");
    return 2;
  }
  char err[256];
  ecat_pdi* pdi = ecat_pdi_connect(argv[1], err, sizeof err);
  if (pdi == nullptr) {
    std::fprintf(stderr, "ecat-bench-pdi: %s\n", err);
    return 1;
  }
  if (ecat_pdi_chip(pdi) != ECAT_PDI_CHIP_DIRECT) {
    std::fprintf(stderr, "ecat-bench-pdi: the host offers an SPI chip; run ecat-slave with --pdi-chip direct\n");
    return 1;
  }
  // No AL event on the IRQ line: ecat_pdi_wait_irq returns for SYNC pulses only.
  const std::uint8_t no_events[4] = {0, 0, 0, 0};
  if (ecat_pdi_esc_write(pdi, kAlEventMask, no_events, sizeof no_events) != 0) return pdi_failed(pdi, "AL event mask");

  std::uint8_t buf[64];
  std::uint64_t ns = 0;
  std::vector<std::int64_t> read2, read64, write2, time_req;
  if (!time_access([&] { return ecat_pdi_esc_read(pdi, kAlStatus, buf, 2); }, accesses, read2) ||
      !time_access([&] { return ecat_pdi_esc_read(pdi, kRamRead, buf, 64); }, accesses, read64) ||
      !time_access([&] { return ecat_pdi_esc_write(pdi, kRamWrite, buf, 2); }, accesses, write2) ||
      !time_access([&] { return ecat_pdi_read_time(pdi, &ns); }, accesses, time_req)) {
    return pdi_failed(pdi, "access");
  }

  // SYNC0 through the project's master over UDP.
  auto ep = transport::parse_udp_endpoint(argv[2]);
  auto udp = ep ? transport::UdpTransport::connect(*ep)
                : Expected<transport::UdpTransport, transport::TransportError>(ecat::fail(ep.error()));
  if (!udp) {
    std::fprintf(stderr, "ecat-bench-pdi: --udp %s: %s\n", argv[2], std::string(transport::describe(udp.error())).c_str());
    return 1;
  }
  SteadyClock clock;
  master::Master m(*udp, clock);
  if (auto n = m.scan(); !n || *n < 1) {
    std::fprintf(stderr, "ecat-bench-pdi: no slave answers at %s\n", argv[2]);
    return 1;
  }
  const auto cycle_ns = static_cast<std::uint32_t>(cycle_us * 1000);
  auto start = m.configure_sync0(0, cycle_ns, 0, std::chrono::milliseconds(100));
  if (!start) {
    std::fprintf(stderr, "ecat-bench-pdi: SYNC0 set-up failed\n");
    return 1;
  }
  // System time (0x0910 through the PDI, read at the host's now) minus
  // CLOCK_MONOTONIC, from the read with the shortest round trip.
  std::int64_t best_rtt = INT64_MAX, system_minus_mono = 0;
  for (int i = 0; i < kCalibrationReads; ++i) {
    const std::int64_t t0 = mono_ns();
    if (ecat_pdi_esc_read(pdi, kSystemTime, buf, 8) != 0) return pdi_failed(pdi, "0x0910");
    const std::int64_t t1 = mono_ns();
    if (t1 - t0 < best_rtt) {
      best_rtt = t1 - t0;
      system_minus_mono = static_cast<std::int64_t>(load_le<std::uint64_t>(buf)) - (t0 + t1) / 2;
    }
  }
  if (ecat_pdi_esc_read(pdi, kStartTime, buf, 8) != 0) return pdi_failed(pdi, "0x0990");
  const std::uint64_t first = load_le<std::uint64_t>(buf);  // the first pulse (not yet come: 100 ms ahead)
  std::vector<std::int64_t> seen, host_part, socket_part;
  std::uint64_t last_k = 0;
  long merged = 0;  // pulses told together with a later one
  ecat_pdi_lines lines{};
  while (static_cast<long>(seen.size()) < pulses) {
    const int r = ecat_pdi_wait_irq(pdi, 1000, &lines);
    const std::int64_t t_seen = mono_ns();
    if (r < 0) return pdi_failed(pdi, "wait for SYNC0");
    if (r == 0) {
      std::fprintf(stderr, "ecat-bench-pdi: no SYNC0 for 1 s\n");
      return 1;
    }
    if ((lines.sync & ECAT_PDI_SYNC0) == 0) continue;
    // The pulse these lines tell of: the latest at or before the host sent
    // them (within the calibration's error), in system time.
    const std::int64_t sent = static_cast<std::int64_t>(lines.time_ns);
    const std::int64_t system_sent = sent + system_minus_mono + best_rtt / 2;
    if (system_sent < static_cast<std::int64_t>(first)) continue;
    const std::uint64_t k = (static_cast<std::uint64_t>(system_sent) - first) / cycle_ns;
    auto pulse_at = [&](std::uint64_t i) {
      return static_cast<std::int64_t>(first + i * cycle_ns) - system_minus_mono;
    };
    // Pulses since the last one seen that came with this one (the host or
    // the firmware a cycle late): seen now, their latency counts too.
    if (!seen.empty()) {
      for (std::uint64_t i = last_k + 1; i < k; ++i) {
        seen.push_back(t_seen - pulse_at(i));
        ++merged;
      }
    }
    last_k = k;
    const std::int64_t pulse = pulse_at(k);
    seen.push_back(t_seen - pulse);
    host_part.push_back(sent - pulse);
    socket_part.push_back(t_seen - sent);
  }
  ecat_pdi_close(pdi);

  std::printf("| %-44s | %7s | %8s | %8s | %9s | %8s |\n", "ecat-slave --pdi-host, direct PDI (µs)", "n", "median",
              "p99", "max", "mean");
  std::printf("|%s|---:|---:|---:|---:|---:|\n", std::string(46, '-').c_str());
  row("READ 2 bytes (AL status), round trip", summarise(read2));
  row("READ 64 bytes (process RAM), round trip", summarise(read64));
  row("WRITE 2 bytes (process RAM), round trip", summarise(write2));
  row("TIME, round trip", summarise(time_req));
  row("SYNC0 -> firmware sees it (wait_irq returns)", summarise(seen));
  row("  of which SYNC0 -> host sends the lines", summarise(host_part));
  row("  of which lines sent -> firmware sees them", summarise(socket_part));
  std::printf("SYNC0 cycle %ld µs; calibration of the ESC's system time to CLOCK_MONOTONIC within ±%.1f µs "
              "(half the shortest 0x0910 round trip); %ld pulse(s) seen only with a later one (a cycle late: counted with their latency)\n",
              cycle_us, static_cast<double>(best_rtt) / 2e3, merged);
  return 0;
}
