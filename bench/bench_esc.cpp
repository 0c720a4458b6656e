// ESC datagram path (issue 8 item 1): one slave - FPRD 2 bytes at 0130h,
// FPWR 2 bytes, ARMW 8 bytes at 0910h, LRW of 1,486 bytes mapped by two
// FMMUs with WKC 3 - and chains of 1/10/100/1000 ESCs carrying one FPRD
// frame and one 1,486-byte LRW frame, and of 1/100 ESCs carrying one BRD
// of AL status. Each iteration is one call of
// Segment::process_frame on a frame built once (parse + every ESC), with the
// time advancing 1 µs per frame so the timers run as in a live cycle.
#include <benchmark/benchmark.h>

#include "bench/bench_options.hpp"
#include "bench/mini_master.hpp"

namespace ecat::bench {
namespace {

constexpr Nanoseconds kFramePeriod{1000};
// A free RAM address (no SM covers it) for the FPWR case.
constexpr std::uint16_t kFreeRam = 0x2800;
constexpr std::uint16_t kSystemTimeBytes = 8;
constexpr std::uint16_t kAlStatusBytes = 2;
constexpr std::uint16_t kWkcLrwBoth = 3;  // read +1, write +2 (ETG.1000.4 §5.4.3)

// Runs `frame` through `segment` once per iteration; checks the WKC of
// datagram 0 grew by `wkc_step` on the first pass.
void run_frames(benchmark::State& state, esc::Segment& segment, Frame& frame, std::uint16_t wkc_step) {
  auto bytes = frame.finish();
  Nanoseconds now{0};
  const std::uint16_t before = frame.wkc(0);
  if (!segment.process_frame(bytes, now) || frame.wkc(0) != static_cast<std::uint16_t>(before + wkc_step)) {
    state.SkipWithError(("unexpected WKC " + std::to_string(frame.wkc(0))).c_str());
    return;
  }
  for (auto _ : state) {
    now += kFramePeriod;
    benchmark::DoNotOptimize(segment.process_frame(bytes, now));
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(bytes.size()));
}

void BM_OneSlave_Fprd2_0130(benchmark::State& state) {
  EscLine line(1);
  Frame f;
  f.add(Command::Fprd, device_address(station(0), esc::reg::kAlStatus), kAlStatusBytes);
  run_frames(state, line.segment, f, 1);
}
BENCHMARK(BM_OneSlave_Fprd2_0130)->Apply(iterations_from_env);

void BM_OneSlave_Fpwr2(benchmark::State& state) {
  EscLine line(1);
  Frame f;
  f.add(Command::Fpwr, device_address(station(0), kFreeRam), le16(0xBEEF));
  run_frames(state, line.segment, f, 1);
}
BENCHMARK(BM_OneSlave_Fpwr2)->Apply(iterations_from_env);

void BM_OneSlave_Armw8_0910(benchmark::State& state) {
  EscLine line(1);
  Frame f;
  f.add(Command::Armw, device_address(auto_increment_adp(0), esc::reg::kDcBase + 0x10), kSystemTimeBytes);
  run_frames(state, line.segment, f, 1);
}
BENCHMARK(BM_OneSlave_Armw8_0910)->Apply(iterations_from_env);

// 1,486 bytes: the first half outputs (FMMU0 write -> SM2), the second half
// inputs (FMMU1 read <- SM3).
void BM_OneSlave_Lrw1486(benchmark::State& state) {
  EscLine line(1);
  constexpr std::uint16_t kOut = kFullFrameData / 2;
  constexpr std::uint16_t kIn = kFullFrameData - kOut;
  map_process_data(line.segment, station(0), 0, kOut, kIn);
  Frame f;
  f.add(Command::Lrw, 0, kFullFrameData);
  run_frames(state, line.segment, f, kWkcLrwBoth);
}
BENCHMARK(BM_OneSlave_Lrw1486)->Apply(iterations_from_env);

// Chains: one FPRD of AL status to the last slave (every ESC checks the address).
void BM_Chain_FprdFrame(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  EscLine line(n);
  Frame f;
  f.add(Command::Fprd, device_address(station(n - 1), esc::reg::kAlStatus), kAlStatusBytes);
  run_frames(state, line.segment, f, 1);
  state.counters["ns_per_slave"] = benchmark::Counter(static_cast<double>(state.iterations() * n),
                                                      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_Chain_FprdFrame)->Apply(iterations_from_env)->Arg(1)->Arg(10)->Arg(100)->Arg(1000);

// Chains: one BRD of AL status (2 bytes), the status poll of every cycle:
// every ESC ORs its AL status in.
void BM_Chain_BrdFrame(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  EscLine line(n);
  Frame f;
  f.add(Command::Brd, device_address(0, esc::reg::kAlStatus), kAlStatusBytes);
  run_frames(state, line.segment, f, static_cast<std::uint16_t>(n));
  state.counters["ns_per_slave"] = benchmark::Counter(static_cast<double>(state.iterations() * n),
                                                      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_Chain_BrdFrame)->Apply(iterations_from_env)->Arg(1)->Arg(100);

// Chains: one 1,486-byte LRW; the slaves share it evenly (half outputs, half
// inputs each, at least 1 + 1 byte); past 743 slaves the shares lie beyond
// the frame, so those ESCs check their FMMUs and map nothing.
void BM_Chain_LrwFrame(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  EscLine line(n);
  const auto share = static_cast<std::uint16_t>(std::max<std::size_t>(2, kFullFrameData / n));
  const auto out = static_cast<std::uint16_t>(share / 2);
  const auto in = static_cast<std::uint16_t>(share - out);
  std::size_t mapped = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto logical = static_cast<std::uint32_t>(i * share);
    map_process_data(line.segment, station(i), logical, out, in);
    if (logical + share <= kFullFrameData) ++mapped;
  }
  Frame f;
  f.add(Command::Lrw, 0, kFullFrameData);
  run_frames(state, line.segment, f, static_cast<std::uint16_t>(kWkcLrwBoth * mapped));
  state.counters["ns_per_slave"] = benchmark::Counter(static_cast<double>(state.iterations() * n),
                                                      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_Chain_LrwFrame)->Apply(iterations_from_env)->Arg(1)->Arg(10)->Arg(100)->Arg(1000);

}  // namespace
}  // namespace ecat::bench

BENCHMARK_MAIN();
