// Where the CSP cycle's time goes (issue 30 item 1): diagnostic cases kept
// apart from bench_esc and bench_cycle, so that adding or changing them
// moves none of the code those programs compare between commits (a case
// added to bench_esc made its one-ESC cases 1.03-1.05x slower with the same
// instructions: docs/performance-log.md "Session 30").
#include <benchmark/benchmark.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <exception>
#include <memory>
#include <span>
#include <string>

#include "bench/bench_options.hpp"
#include "bench/drive_line.hpp"
#include "bench/mini_master.hpp"

namespace ecat::bench {
namespace {

// BM_Cycle_Csp's line of state.range(0) drives, or null with the case
// skipped and the reason given. bench_cycle has its own: the same helper
// shared through a header changed how GCC compiled an unrelated function
// there and moved that program's code by 32 bytes, enough to make its
// one-drive cycle 1.04x slower with the same instructions (docs/performance-log.md
// "Session 30"), so the compared program keeps its bytes.
std::unique_ptr<DriveLine> make_line(benchmark::State& state) {
  try {
    auto line = std::make_unique<DriveLine>(static_cast<std::size_t>(state.range(0)), DriveLine::default_device());
    advise_huge_pages_from_env();
    return line;
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return nullptr;
  }
}

// The drives must still be enabled after the measured cycles.
void report(benchmark::State& state, DriveLine& line) {
  const auto n = static_cast<std::size_t>(state.range(0));
  if ((line.statusword(n - 1) & kSwStateMask) != kSwOperationEnabled) state.SkipWithError("drive dropped out");
  state.counters["frames"] = static_cast<double>(line.frames());
  state.counters["ns_per_drive"] = benchmark::Counter(static_cast<double>(state.iterations() * n),
                                                      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// Where BM_Cycle_Csp's time goes (issue 30 item 1), in wall time per drive
// and cycle (steady_clock around each half of Chain::process_frame, as
// ecat-bench-lines splits the cycle for scripts/lines-per-drive's cache
// model): the first frame's pass through the ESCs (ARMW 0910h, BRD 0130h,
// its LRW), the firmware after it (every drive's application cycle: their
// timers came due before the frame), the other frames' passes (LRWs that
// enter only the ESCs they map), the firmware after those, and the rest
// (set-points, the poll). Three clock reads a frame and two a cycle aside,
// the counters add up to the case's time; the A/B reference stays
// BM_Cycle_Csp.
struct PhaseClock {
  slave::Chain& chain;
  std::size_t frames = 1;
  std::size_t seen = 0;
  std::array<std::chrono::steady_clock::duration, 4> spent{};  // first pass, first firmware, passes, firmware
  bool process_frame(std::span<std::uint8_t> frame, Nanoseconds now) noexcept {
    const auto a = std::chrono::steady_clock::now();
    const bool returned = chain.pass_frame(frame, now);
    const auto b = std::chrono::steady_clock::now();
    chain.run_firmware(now);
    const auto c = std::chrono::steady_clock::now();
    const std::size_t at = seen++ % frames == 0 ? 0 : 2;
    spent[at] += b - a;
    spent[at + 1] += c - b;
    return returned;
  }
};
void BM_Cycle_CspPhases(benchmark::State& state) {
  std::unique_ptr<DriveLine> line = make_line(state);
  if (!line) return;
  PhaseClock phases{line->chain(), line->frames()};
  std::chrono::steady_clock::duration all{};
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    line->cycle(phases);
    all += std::chrono::steady_clock::now() - start;
  }
  report(state, *line);
  const double per = static_cast<double>(state.iterations()) * static_cast<double>(state.range(0));
  const auto ns = [per](std::chrono::steady_clock::duration d) {
    return static_cast<double>(std::chrono::duration_cast<std::chrono::nanoseconds>(d).count()) / per;
  };
  state.counters["first_pass"] = ns(phases.spent[0]);
  state.counters["first_firmware"] = ns(phases.spent[1]);
  state.counters["passes"] = ns(phases.spent[2]);
  state.counters["firmware"] = ns(phases.spent[3]);
  state.counters["rest"] = ns(all - phases.spent[0] - phases.spent[1] - phases.spent[2] - phases.spent[3]);
}
BENCHMARK(BM_Cycle_CspPhases)->Apply(iterations_from_env)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);

// BM_Cycle_Csp with the drives switched to another synchronisation mode by
// `to_mode` (a DriveLine member); the drives must still be in Op after the
// measured cycles.
void run_in_mode(benchmark::State& state, void (DriveLine::*to_mode)()) {
  std::unique_ptr<DriveLine> line = make_line(state);
  if (!line) return;
  try {
    ((*line).*to_mode)();
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  for (auto _ : state) line->cycle();
  const auto n = static_cast<std::size_t>(state.range(0));
  for (std::size_t d = 0; d < n; ++d) {
    if (line->al_status(d) != static_cast<std::uint16_t>(od::EsmState::Op)) {
      state.SkipWithError(("slave " + std::to_string(d) + " left Op, AL status " +
                           std::to_string(line->al_status(d)))
                              .c_str());
      return;
    }
  }
  report(state, *line);
}

// DC Sync0 mode (1C32h:01 = 2), as servo drives run under TwinCAT, SOEM or
// IgH with DC: the application cycle runs on SYNC0 (half a cycle after the
// frames) instead of the free-run timer, and the firmware also answers each
// LRW's SM2 event (new outputs noted against SYNC0, ETG.1020 §5.2.2); a sync
// error would take a drive out of Op.
void BM_Cycle_CspDc(benchmark::State& state) { run_in_mode(state, &DriveLine::to_dc_sync0); }
BENCHMARK(BM_Cycle_CspDc)->Apply(iterations_from_env)->Arg(1)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);

// SM-synchronous (1C32h:01 = 1, 1C33h:01 = 22h): the application cycle runs
// on each SM2 event, as under a master without DC (SOEM's and IgH's default).
void BM_Cycle_CspSm(benchmark::State& state) { run_in_mode(state, &DriveLine::to_sm_synchronous); }
BENCHMARK(BM_Cycle_CspSm)->Apply(iterations_from_env)->Arg(1)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);

constexpr std::uint16_t kWkcLrwBoth = 3;  // read +1, write +2 (ETG.1000.4 §5.4.3)
constexpr Nanoseconds kFramePeriod{1000};

// A chain of state.range(0) ESCs whose process data (kSliceShare bytes
// each, half outputs, half inputs) lies in one logical image, and one LRW
// over the shares of kSliceEscs of them in the middle: the shape of the
// 1000-drive CSP cycle's later frames (BM_Cycle_CspPhases' "passes"), where
// the frame enters only the ESCs it maps and passes the others by (the skip
// index, esc::Segment::carry_line). No firmware touches the ESCs between
// frames, so the entered ones stay in the caches: the path's own cost.
constexpr std::size_t kSliceEscs = 48;
constexpr std::uint16_t kSliceShare = 30;
void BM_Chain_LrwSlice(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  EscLine line(n);
  constexpr auto kOut = static_cast<std::uint16_t>(kSliceShare / 2);
  constexpr auto kIn = static_cast<std::uint16_t>(kSliceShare - kOut);
  for (std::size_t i = 0; i < n; ++i) {
    map_process_data(line.segment, station(i), static_cast<std::uint32_t>(i * kSliceShare), kOut, kIn);
  }
  const std::size_t first = (n - kSliceEscs) / 2;
  Frame f;
  f.add(Command::Lrw, static_cast<std::uint32_t>(first * kSliceShare),
        static_cast<std::uint16_t>(kSliceEscs * kSliceShare));
  auto bytes = f.finish();
  Nanoseconds now{0};
  if (!line.segment.process_frame(bytes, now) || f.wkc(0) != kWkcLrwBoth * kSliceEscs) {
    state.SkipWithError(("unexpected WKC " + std::to_string(f.wkc(0))).c_str());
    return;
  }
  for (auto _ : state) {
    now += kFramePeriod;  // the timers run as in a live cycle
    benchmark::DoNotOptimize(line.segment.process_frame(bytes, now));
    benchmark::ClobberMemory();
  }
  state.counters["ns_per_entered"] = benchmark::Counter(static_cast<double>(state.iterations() * kSliceEscs),
                                                        benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_Chain_LrwSlice)->Apply(iterations_from_env)->Arg(100)->Arg(1000);

}  // namespace
}  // namespace ecat::bench

BENCHMARK_MAIN();
