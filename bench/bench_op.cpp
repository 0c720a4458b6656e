// The chain of N generic servo drives taken from power-on to Op by the
// project's master (master/) over the in-memory transport, one process
// (issue 16 item 5: 1000 drives in under 5 s). Wall time of one run, and the
// frames each phase sends (slave::Chain stats), per phase: scan (counts,
// station addresses, SII images), mailbox SMs + PreOp, PDO sizes over SDO,
// process data + SafeOp, Op (5 cycles in SafeOp, the Op request, 1 cycle). The simulated clock advances 50 µs per frame
// as in tests/master/in_process_bus.hpp; what is timed is the CPU work of
// master and slaves, not simulated time.
#include <benchmark/benchmark.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "esi/device_loader.hpp"
#include "master/coe_client.hpp"
#include "master/master.hpp"
#include "slave/chain.hpp"
#include "transport/in_memory_transport.hpp"

namespace ecat::bench {
namespace {

constexpr Nanoseconds kFrameTime{50'000};

struct Bus {
  ManualClock clock;
  slave::Chain chain{clock};
  transport::InMemoryTransport transport{[this](Bytes f) {
    if (!chain.process_frame(f, clock.now())) transport.drop_next(1);
    clock.advance(kFrameTime);
  }};
};

// `strings`: MasterConfig::read_sii_strings (off: the scan leaves the SII
// STRINGS category out, about half of a generic servo's image).
void chain_to_op(benchmark::State& state, bool strings) {
  const auto n = static_cast<std::size_t>(state.range(0));
  auto dev = esi::load_device_file(std::string(ECAT_SOURCE_DIR) + "/xml/devices/generic-servo.xml");
  if (!dev) {
    state.SkipWithError(dev.error().to_string().c_str());
    return;
  }
  const auto device = std::make_shared<const od::DeviceDescription>(std::move(*dev));
  // Wall seconds and frames per phase, last iteration.
  double t_scan = 0, t_preop = 0, t_pdo = 0, t_safeop = 0, t_op = 0;
  std::uint64_t f_scan = 0, f_preop = 0, f_pdo = 0, f_safeop = 0, f_op = 0;
  int reached = 0;  // AL state the run ended in (8 Op)
  std::uint16_t cycle_frames = 0;  // frames of one cyclic exchange
  for (auto _ : state) {
    state.PauseTiming();
    auto bus = std::make_unique<Bus>();
    for (std::size_t i = 0; i < n; ++i) {
      slave::SlaveOptions o;
      o.name = "slave-" + std::to_string(i + 1);
      if (auto r = bus->chain.add(device, o); !r) {
        state.SkipWithError(r.error().c_str());
        return;
      }
    }
    master::MasterConfig cfg;
    cfg.state_timeout = std::chrono::seconds(30);  // simulated time: 1000 slaves x frames
    cfg.max_slaves = n;
    cfg.read_sii_strings = strings;
    master::Master m(bus->transport, bus->clock, cfg);
    state.ResumeTiming();
    using Wall = std::chrono::steady_clock;
    auto t0 = Wall::now();
    std::uint64_t f0 = bus->chain.stats().frames_received;
    auto lap = [&](double& t, std::uint64_t& f) {
      const auto now = Wall::now();
      t = std::chrono::duration<double>(now - t0).count();
      f = bus->chain.stats().frames_received - f0;
      t0 = now;
      f0 = bus->chain.stats().frames_received;
    };
    auto fail = [&](const char* what) { state.SkipWithError(what); };
    if (auto sc = m.scan(); !sc || *sc != n) {
      const std::string why = sc ? "scan found " + std::to_string(*sc) : "scan: " + std::string(master::describe(sc.error()));
      return fail(why.c_str());
    }
    lap(t_scan, f_scan);
    // Mailbox SMs of all slaves side by side (master/mailbox.cpp).
    if (auto mb = m.configure_mailboxes(); !mb || *mb != n) return fail("configure_mailboxes");
    if (!m.request_state_all(master::AlState::PreOp)) return fail("PreOp");
    lap(t_preop, f_preop);
    // PDO sizes over SDO, the slaves' mailbox steps side by side (master/pdo_sizes_batch.cpp).
    std::vector<std::size_t> all(n);
    for (std::size_t i = 0; i < n; ++i) all[i] = i;
    if (!master::read_pdo_sizes_all(m, all)) return fail("read_pdo_sizes_all");
    lap(t_pdo, f_pdo);
    // The image over as many LRW datagrams and frames as it needs (master/process_image_plan.hpp).
    if (auto pd = m.configure_process_data(); !pd) return fail("configure_process_data");
    if (!m.request_state_all(master::AlState::SafeOp)) return fail("SafeOp");
    lap(t_safeop, f_safeop);
    for (int i = 0; i < 5; ++i) {
      if (!m.exchange_process_data()) return fail("exchange_process_data");
    }
    if (!m.request_state_all(master::AlState::Op)) return fail("Op");
    auto r = m.exchange_process_data();
    if (!r || !r->ok()) return fail("WKC in Op");
    cycle_frames = r->frames;
    lap(t_op, f_op);
    reached = 8;
    state.PauseTiming();
    bus.reset();
    state.ResumeTiming();
  }
  state.counters["reached"] = reached;
  state.counters["cycle_frames"] = cycle_frames;
  state.counters["s_scan"] = t_scan;
  state.counters["s_preop"] = t_preop;
  state.counters["s_pdo"] = t_pdo;
  state.counters["s_safeop"] = t_safeop;
  state.counters["s_op"] = t_op;
  state.counters["frames_scan"] = static_cast<double>(f_scan);
  state.counters["frames_preop"] = static_cast<double>(f_preop);
  state.counters["frames_pdo"] = static_cast<double>(f_pdo);
  state.counters["frames_safeop"] = static_cast<double>(f_safeop);
  state.counters["frames_op"] = static_cast<double>(f_op);
}
void BM_ChainToOp(benchmark::State& state) { chain_to_op(state, true); }
void BM_ChainToOpWithoutStrings(benchmark::State& state) { chain_to_op(state, false); }
BENCHMARK(BM_ChainToOp)->Arg(10)->Arg(100)->Arg(1000)->Iterations(1)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ChainToOpWithoutStrings)
    ->Arg(10)
    ->Arg(100)
    ->Arg(1000)
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ecat::bench

BENCHMARK_MAIN();
