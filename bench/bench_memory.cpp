// Resident memory per emulated slave (issue 8 item 1): VmRSS of this process
// before and after building a chain of 1,000 generic servo drives and taking
// them to Op with CSP running (bench/drive_line.hpp), divided by 1,000.
// Reported with and without the ESC's 64 KiB address space (registers +
// process RAM, allocated and zeroed once per ESC). Target: <= 256 KiB per
// slave beyond its process RAM.
#include <benchmark/benchmark.h>

#include <fstream>
#include <string>

#include "bench/drive_line.hpp"

namespace ecat::bench {
namespace {

long rss_kib() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  }
  return -1;
}

void BM_Memory_PerSlave(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  double per_slave = 0;
  for (auto _ : state) {
    const long before = rss_kib();
    DriveLine line(n);
    for (int i = 0; i < 10; ++i) line.cycle();
    per_slave = static_cast<double>(rss_kib() - before) / static_cast<double>(n);
  }
  constexpr double kAddressSpaceKib = static_cast<double>(esc::kAddressSpace) / 1024.0;
  state.counters["KiB_per_slave"] = per_slave;
  state.counters["KiB_beyond_esc_memory"] = per_slave - kAddressSpaceKib;
}
BENCHMARK(BM_Memory_PerSlave)->Arg(1000)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ecat::bench

BENCHMARK_MAIN();
