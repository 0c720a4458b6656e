// A full CSP cycle of N CiA 402 drives (issue 8 item 1): the LRW frames with
// every drive's process data, ARMW 0910h for DC, BRD 0130h of AL status,
// and every drive's firmware and application cycle (bench/drive_line.hpp).
// Target: 100 drives <= 9 µs per cycle on one core, linear in N.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>

#include "bench/bench_options.hpp"
#include "bench/drive_line.hpp"
#include "control/control_server.hpp"
#include "slave/fault_catalogue.hpp"
#include "slave/lane_choice.hpp"
#include "bench/http_page.hpp"

namespace ecat::bench {
namespace {

// The case's line of state.range(0) drives, or null with the case skipped
// and the reason given when it cannot be built.
std::unique_ptr<DriveLine> make_line(benchmark::State& state, std::size_t branch = 0) {
  try {
    auto line = std::make_unique<DriveLine>(static_cast<std::size_t>(state.range(0)), DriveLine::default_device(), branch);
    advise_huge_pages_from_env();
    return line;
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return nullptr;
  }
}

// After the measured cycles: the drives must have followed (still enabled,
// else the case is reported as skipped); the frames per cycle and the time
// per drive.
void report(benchmark::State& state, DriveLine& line) {
  const auto n = static_cast<std::size_t>(state.range(0));
  if ((line.statusword(n - 1) & kSwStateMask) != kSwOperationEnabled) {
    const std::string why = "drive dropped out: statusword " + std::to_string(line.statusword(n - 1)) +
                            " error " + std::to_string(line.error_code(n - 1)) + " AL status " +
                            std::to_string(line.al_status(n - 1));
    state.SkipWithError(why.c_str());
  }
  state.counters["frames"] = static_cast<double>(line.frames());
  state.counters["ns_per_drive"] = benchmark::Counter(static_cast<double>(state.iterations() * n),
                                                      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// The CSP cycle of state.range(0) drives, skipping on or off, with the
// drives still enabled afterwards (else the case is reported as skipped).
// With `control`: the control interface on and idle, as ecat-slave runs it
// with --control and no client (docs/control.md): a Unix socket server
// serviced after every cycle, doing its tick's work (poll of the socket,
// event sample) every 10 ms of the simulated time.
void run_cycles(benchmark::State& state, bool skipping, bool control = false, std::size_t branch = 0) {
  std::unique_ptr<DriveLine> line = make_line(state, branch);
  if (!line) return;
  line->chain().set_skipping(skipping);
  ManualClock clock;
  control::EventQueue events;
  std::unique_ptr<slave::FaultCatalogue> faults;
  std::unique_ptr<control::RequestHandler> handler;
  std::unique_ptr<control::ControlServer> server;
  if (control) {
    faults = std::make_unique<slave::FaultCatalogue>(line->chain());
    handler = std::make_unique<control::RequestHandler>(line->chain(), clock, events, faults.get());
    const std::string path =
        (std::filesystem::temp_directory_path() / ("bench-control-" + std::to_string(::getpid()))).string();
    auto s = control::ControlServer::open(path, *handler);
    if (!s) {
      state.SkipWithError(s.error().c_str());
      return;
    }
    server = std::move(*s);
  }
  if (server) {
    for (auto _ : state) {
      line->cycle();
      server->service(line->now());
    }
  } else {
    for (auto _ : state) line->cycle();
  }
  report(state, *line);
}


void BM_Cycle_Csp(benchmark::State& state) { run_cycles(state, true); }
BENCHMARK(BM_Cycle_Csp)->Apply(iterations_from_env)->Arg(1)->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);

// BM_Cycle_Csp as ecat-slave's live loop runs it: every read of the slaves'
// clock also costs a read of the host's steady clock (bench/bench_clock.hpp),
// which the simulated clock of the other cases does not. reads_per_drive:
// the clock reads a drive's cycle makes (the chain's, its ESC's and its
// firmware's), counted.
void BM_Cycle_CspLiveClock(benchmark::State& state) {
  std::unique_ptr<DriveLine> line = make_line(state);
  if (!line) return;
  line->clock().live_reads(true);
  const std::uint64_t before = line->clock().reads();
  for (auto _ : state) line->cycle();
  const std::uint64_t reads = line->clock().reads() - before;
  line->clock().live_reads(false);
  report(state, *line);
  state.counters["reads_per_drive"] = static_cast<double>(reads) /
                                      static_cast<double>(state.iterations() * static_cast<std::uint64_t>(state.range(0)));
}
BENCHMARK(BM_Cycle_CspLiveClock)->Apply(iterations_from_env)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);

// BM_Cycle_Csp with the firmware on state.range(1) threads (issue 30 item
// 3, slave::Chain::set_firmware_threads), in wall time: the helpers spin,
// so the CPU time they add is the cost and the wall time the gain. The
// one-thread rows are the reference in the same run. 200 and 1000 drives:
// below Chain::kMinSplitSlaves busy slaves nothing is split.
void BM_Cycle_CspLanes(benchmark::State& state) {
  std::unique_ptr<DriveLine> line = make_line(state);
  if (!line) return;
  if (auto ok = line->chain().set_firmware_threads(static_cast<unsigned>(state.range(1))); !ok) {
    state.SkipWithError(ok.error().c_str());
    return;
  }
  for (auto _ : state) line->cycle();
  report(state, *line);
}
BENCHMARK(BM_Cycle_CspLanes)
    ->Apply(iterations_from_env)
    ->Args({200, 1})
    ->Args({200, 2})
    ->Args({1000, 1})
    ->Args({1000, 2})
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond);

// What BM_Cycle_CspLanes depends on most: the time a cache line takes to go
// from one core to the other and back (an atomic bounced between this
// thread and a second one, as the lanes' hand-off and the ESC lines a
// helper wrote do). On this project's 2-vCPU VM it measured 86-229 ns most
// of the time and 470 ns for a while, when two threads were slower than one
// (docs/performance-log.md "Firmware lanes").
// Each iteration is one slave::cache_line_round_trip (the probe of
// ecat-slave --firmware-threads auto, ~1 ms), its median trip as the
// iteration's time: the row's time is the mean of 20 probes' figures.
constexpr int kRoundTripProbes = 20;
void BM_Lanes_CacheLineRoundTrip(benchmark::State& state) {
  for (auto _ : state) {
    state.SetIterationTime(std::chrono::duration<double>(slave::cache_line_round_trip()).count());
  }
}
BENCHMARK(BM_Lanes_CacheLineRoundTrip)->UseManualTime()->Iterations(kRoundTripProbes)->Unit(benchmark::kNanosecond);

// BM_Cycle_Csp with every frame passed through a fault catalogue with
// nothing engaged (issue 26 item 5: the idle cost must be nil;
// docs/faults.md "Cost"). The reference is BM_Cycle_Csp in the same run.
void BM_Cycle_CspFaultsIdle(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  std::unique_ptr<DriveLine> line = make_line(state);
  if (!line) return;
  slave::FaultCatalogue faults(line->chain());
  for (auto _ : state) line->cycle(faults);
  if ((line->statusword(n - 1) & kSwStateMask) != kSwOperationEnabled) state.SkipWithError("drive dropped out");
  state.counters["ns_per_drive"] = benchmark::Counter(static_cast<double>(state.iterations() * n),
                                                      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_Cycle_CspFaultsIdle)
    ->Apply(iterations_from_env)
    ->Arg(1)
    ->Arg(10)
    ->Arg(100)
    ->Arg(1000)
    ->Unit(benchmark::kMicrosecond);

// The same cycle with skipping off (issue 16 item 5): every frame enters
// every ESC and every slave is asked after every frame, as before the skip.
// The reference for BM_Cycle_Csp in the same binary and the same minutes.
void BM_Cycle_CspFullPass(benchmark::State& state) { run_cycles(state, false); }
BENCHMARK(BM_Cycle_CspFullPass)->Apply(iterations_from_env)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);

// The same cycle on a tree (issue 30 item 2: within 1.2x of BM_Cycle_Csp):
// junctions every 10 drives, each with a branch of 9 drives on its port 3
// (DriveLine's `branch`), skipping on, and off (the port walk). At 1 drive
// the tree is one four-port junction, at 10 a junction and its branch
// (the per-drive rows of scripts/bench-table).
constexpr std::size_t kTreeBranch = 10;
void BM_Cycle_CspTree(benchmark::State& state) { run_cycles(state, true, false, kTreeBranch); }
BENCHMARK(BM_Cycle_CspTree)
    ->Apply(iterations_from_env)
    ->Arg(1)
    ->Arg(10)
    ->Arg(100)
    ->Arg(1000)
    ->Unit(benchmark::kMicrosecond);
void BM_Cycle_CspTreeFullPass(benchmark::State& state) { run_cycles(state, false, false, kTreeBranch); }
BENCHMARK(BM_Cycle_CspTreeFullPass)->Apply(iterations_from_env)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);

// BM_Cycle_Csp with the control interface on and idle (issue 26 item 5:
// within 2 % of BM_Cycle_Csp in the same run).
void BM_Cycle_CspControlIdle(benchmark::State& state) { run_cycles(state, true, true); }
BENCHMARK(BM_Cycle_CspControlIdle)->Apply(iterations_from_env)->Arg(1)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);

// BM_Cycle_Csp with ecat-slave --http on (issue 27 item 6, docs/performance.md):
// the web server serviced after every cycle as the live loop does, either
// with no page (Idle) or with one page's event stream connected (Page: a
// client thread reading GET /events, so the loop samples events every 10 ms
// and builds a snapshot of the network every 200 ms).
void run_http(benchmark::State& state, bool page) {
  const auto n = static_cast<std::size_t>(state.range(0));
  std::unique_ptr<DriveLine> line = make_line(state);
  if (!line) return;
  HttpPage http(line->chain(), page);
  if (!http.error.empty()) {
    state.SkipWithError(http.error.c_str());
    return;
  }
  const std::size_t connect_cycles = http.wait_connected([&] {
    line->cycle();
    http.server->service(line->now());
  });
  for (auto _ : state) {
    line->cycle();
    http.server->service(line->now());
  }
  if ((line->statusword(n - 1) & kSwStateMask) != kSwOperationEnabled) state.SkipWithError("drive dropped out");
  state.counters["stream_bytes"] = static_cast<double>(http.bytes());
  state.counters["connect_cycles"] = static_cast<double>(connect_cycles);
}
void BM_Cycle_CspHttpIdle(benchmark::State& state) { run_http(state, false); }
BENCHMARK(BM_Cycle_CspHttpIdle)->Apply(iterations_from_env)->Arg(1)->Arg(100)->Unit(benchmark::kMicrosecond);
void BM_Cycle_CspHttpPage(benchmark::State& state) { run_http(state, true); }
BENCHMARK(BM_Cycle_CspHttpPage)->Apply(iterations_from_env)->Arg(1)->Arg(100)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace ecat::bench

BENCHMARK_MAIN();
