// Resident memory per emulated slave (issue 8 item 1, issue 16 item 5): VmRSS
// of this process before and after building a chain of N slaves sharing one
// device description and taking them to Op (bench/drive_line.hpp), divided
// by N: 1,000 generic servo drives with CSP running, and 10,000 32-channel
// I/O slaves (tests/data/devices/io-32ch.xml) with their process data
// cycling. Reported with and without the ESC's memory (registers 0x0000-
// 0x0FFF + the configured process RAM, Esc::memory_size()). Target
// (issue 16): <= 32 KiB per slave beyond the program.
#include <benchmark/benchmark.h>

#include <fstream>
#include <string>

#include "bench/bench_options.hpp"
#include "bench/drive_line.hpp"
#include "esi/device_loader.hpp"

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

std::shared_ptr<const od::DeviceDescription> io_device() {
  auto d = esi::load_device_file(std::string(ECAT_SOURCE_DIR) + "/tests/data/devices/io-32ch.xml");
  if (!d) throw std::runtime_error(d.error().to_string());
  return std::make_shared<const od::DeviceDescription>(std::move(*d));
}

void measure(benchmark::State& state, bool io) {
  const auto n = static_cast<std::size_t>(state.range(0));
  double per_slave = 0;
  double esc_kib = 0;
  constexpr int kCycles = 10;
  for (auto _ : state) {
    auto dev = io ? io_device() : nullptr;
    const long before = rss_kib();
    auto line = io ? std::make_unique<DriveLine>(n, dev) : std::make_unique<DriveLine>(n);
    advise_huge_pages_from_env();
    for (int i = 0; i < kCycles; ++i) line->cycle();
    per_slave = static_cast<double>(rss_kib() - before) / static_cast<double>(n);
    esc_kib = static_cast<double>(line->chain()[0].esc().memory_size()) / 1024.0;
    if (line->al_status(n - 1) != static_cast<std::uint16_t>(od::EsmState::Op)) state.SkipWithError("not in Op");
  }
  state.counters["KiB_per_slave"] = per_slave;
  state.counters["KiB_esc_mapped"] = esc_kib;  // registers + RAM mapped; resident: the pages touched
  state.counters["KiB_beyond_esc_mapped"] = per_slave - esc_kib;
}

void BM_Memory_PerSlave(benchmark::State& state) { measure(state, false); }
void BM_Memory_IoSlave(benchmark::State& state) { measure(state, true); }
BENCHMARK(BM_Memory_PerSlave)->Arg(1000)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Memory_IoSlave)->Arg(10000)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ecat::bench

BENCHMARK_MAIN();
