// SPDX-License-Identifier: Apache-2.0
// The cases of bench/bench_esc.cpp driven through KickCAT's EmulatedESC, for
// the comparison of issue 30's done-when. Not part of the CMake build:
// scripts/bench-kickcat compiles it against a KickCAT source tree given on
// its command line (only KickCAT's public API is called; nothing of KickCAT
// is in this repository). Same names as bench_esc's cases so that the script
// can pair them.
//
// Each iteration is one EmulatedNetwork::route() of a frame built once: the
// path KickCAT's network simulator takes for every frame it receives (every
// datagram through every ESC of a line, in order). As in bench_esc, the
// frame is reused as it came back (WKC and ADP keep counting) and the first
// pass checks the WKC. Differences in the work: docs/performance-log.md
// ("KickCAT's EmulatedESC against bench_esc").
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "kickcat/ESC/EmulatedESC.h"
#include "kickcat/EmulatedNetwork.h"
#include "kickcat/Frame.h"
#include "kickcat/protocol.h"

namespace {

using kickcat::Command;
using kickcat::createAddress;

constexpr std::uint16_t kFirstStation = 0x1001;
constexpr std::uint16_t kAlControl = 0x0120;
constexpr std::uint16_t kAlStatus = 0x0130;
constexpr std::uint16_t kSystemTime = 0x0910;
constexpr std::uint16_t kFmmuBase = 0x0600;
constexpr std::uint16_t kSmBase = 0x0800;
// bench_esc writes free process RAM (0x2800, no SM); KickCAT refuses an ECAT
// write to RAM no SM or FMMU covers (no copy, WKC 0), so its case writes
// user RAM (0x0F80), which it copies like any register (WKC 1).
constexpr std::uint16_t kUserRam = 0x0F80;
constexpr std::uint16_t kFullFrameData = kickcat::MAX_ETHERCAT_PAYLOAD_SIZE;  // 1486
constexpr std::uint16_t kSmOutputsStart = 0x1100;
constexpr std::uint16_t kSmInputsStart = 0x1A00;
constexpr std::uint16_t kWkcLrwBoth = 3;

std::uint16_t station(std::size_t i) { return static_cast<std::uint16_t>(kFirstStation + i); }
std::uint16_t auto_increment(std::size_t i) { return static_cast<std::uint16_t>(0 - i); }

// N EmulatedESCs in KickCAT's default line (slave i port 1 to slave i+1 port 0).
struct KcLine {
  explicit KcLine(std::size_t n) {
    std::vector<kickcat::EmulatedESC*> raw;
    for (std::size_t i = 0; i < n; ++i) {
      escs.push_back(std::make_unique<kickcat::EmulatedESC>());
      // EEPROM word 0 high byte bit 0: device emulation (AL status follows AL
      // control), so that the set-up below can take the ESM to SAFE-OP.
      escs.back()->loadEeprom(std::vector<std::uint16_t>{0x0100, 0, 0, 0, 0, 0, 0, 0});
      raw.push_back(escs.back().get());
    }
    net = std::make_unique<kickcat::EmulatedNetwork>(std::move(raw));
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint16_t st = station(i);
      transact(Command::APWR, createAddress(auto_increment(i), kickcat::reg::STATION_ADDR), &st, sizeof(st));
    }
  }
  // One datagram in a frame of its own, routed once (set-up).
  std::uint16_t transact(Command c, std::uint32_t address, void const* data, std::uint16_t size) {
    kickcat::Frame f;
    f.addDatagram(0, c, address, data, size);
    f.finalize();
    net->route(f);
    f.resetContext();
    auto [h, d, wkc] = f.peekDatagram();
    return *wkc;
  }
  std::vector<std::unique_ptr<kickcat::EmulatedESC>> escs;
  std::unique_ptr<kickcat::EmulatedNetwork> net;
};

// KickCAT takes SM and FMMU settings at the ESM transitions (SMs at INIT ->
// PRE-OP, FMMUs at PRE-OP -> SAFE-OP), so the slave is taken there. SM2/SM3
// are 3-buffered as in bench_esc (KickCAT leaves those to the FMMUs).
void map_process_data(KcLine& line, std::uint16_t st, std::uint32_t logical, std::uint16_t out, std::uint16_t in) {
  const std::uint16_t preop = kickcat::State::PRE_OP;
  const std::uint16_t safeop = kickcat::State::SAFE_OP;
  line.transact(Command::FPWR, createAddress(st, kAlControl), &preop, sizeof(preop));
  kickcat::SyncManager::Register sm2{kSmOutputsStart, out, 0x64, 0, 1, 0};
  kickcat::SyncManager::Register sm3{kSmInputsStart, in, 0x20, 0, 1, 0};
  line.transact(Command::FPWR, createAddress(st, kSmBase + 2 * sizeof(sm2)), &sm2, sizeof(sm2));
  line.transact(Command::FPWR, createAddress(st, kSmBase + 3 * sizeof(sm3)), &sm3, sizeof(sm3));
  kickcat::fmmu::Register f0{logical, out, 0, 7, kSmOutputsStart, 0, 2, 1, {}};
  kickcat::fmmu::Register f1{logical + out, in, 0, 7, kSmInputsStart, 0, 1, 1, {}};
  line.transact(Command::FPWR, createAddress(st, kFmmuBase), &f0, sizeof(f0));
  line.transact(Command::FPWR, createAddress(st, kFmmuBase + sizeof(f0)), &f1, sizeof(f1));
  line.transact(Command::FPWR, createAddress(st, kAlControl), &safeop, sizeof(safeop));
}

void run_frames(benchmark::State& state, KcLine& line, Command c, std::uint32_t address, std::uint16_t size,
                std::uint16_t wkc_step, void const* data = nullptr) {
  std::vector<std::uint8_t> zeros(size, 0);
  kickcat::Frame f;
  f.addDatagram(0, c, address, data != nullptr ? data : zeros.data(), size);
  const int32_t bytes = f.finalize();
  if (!line.net->route(f)) {
    state.SkipWithError("frame destroyed");
    return;
  }
  f.resetContext();
  auto [h, d, wkc] = f.peekDatagram();
  if (*wkc != wkc_step) {
    state.SkipWithError(("unexpected WKC " + std::to_string(*wkc)).c_str());
    return;
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(line.net->route(f));
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * bytes);
}

void per_slave(benchmark::State& state, std::size_t n) {
  state.counters["ns_per_slave"] = benchmark::Counter(static_cast<double>(state.iterations() * n),
                                                      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_OneSlave_Fprd2_0130(benchmark::State& state) {
  KcLine line(1);
  run_frames(state, line, Command::FPRD, createAddress(station(0), kAlStatus), 2, 1);
}
BENCHMARK(BM_OneSlave_Fprd2_0130);

void BM_OneSlave_Fpwr2(benchmark::State& state) {
  KcLine line(1);
  const std::uint16_t v = 0xBEEF;
  run_frames(state, line, Command::FPWR, createAddress(station(0), kUserRam), 2, 1, &v);
}
BENCHMARK(BM_OneSlave_Fpwr2);

void BM_OneSlave_Armw8_0910(benchmark::State& state) {
  KcLine line(1);
  run_frames(state, line, Command::ARMW, createAddress(auto_increment(0), kSystemTime), 8, 1);
}
BENCHMARK(BM_OneSlave_Armw8_0910);

void BM_OneSlave_Lrw1486(benchmark::State& state) {
  KcLine line(1);
  constexpr std::uint16_t kOut = kFullFrameData / 2;
  map_process_data(line, station(0), 0, kOut, kFullFrameData - kOut);
  run_frames(state, line, Command::LRW, 0, kFullFrameData, kWkcLrwBoth);
}
BENCHMARK(BM_OneSlave_Lrw1486);

void BM_Chain_FprdFrame(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  KcLine line(n);
  run_frames(state, line, Command::FPRD, createAddress(station(n - 1), kAlStatus), 2, 1);
  per_slave(state, n);
}
BENCHMARK(BM_Chain_FprdFrame)->Arg(1)->Arg(10)->Arg(100)->Arg(1000);

void BM_Chain_BrdFrame(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  KcLine line(n);
  run_frames(state, line, Command::BRD, createAddress(0, kAlStatus), 2, static_cast<std::uint16_t>(n));
  per_slave(state, n);
}
BENCHMARK(BM_Chain_BrdFrame)->Arg(1)->Arg(100);

void BM_Chain_LrwFrame(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  KcLine line(n);
  const auto share = static_cast<std::uint16_t>(std::max<std::size_t>(2, kFullFrameData / n));
  const auto out = static_cast<std::uint16_t>(share / 2);
  const auto in = static_cast<std::uint16_t>(share - out);
  std::size_t mapped = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto logical = static_cast<std::uint32_t>(i * share);
    map_process_data(line, station(i), logical, out, in);
    if (logical + share <= kFullFrameData) ++mapped;
  }
  run_frames(state, line, Command::LRW, 0, kFullFrameData, static_cast<std::uint16_t>(kWkcLrwBoth * mapped));
  per_slave(state, n);
}
BENCHMARK(BM_Chain_LrwFrame)->Arg(1)->Arg(10)->Arg(100)->Arg(1000);

}  // namespace

BENCHMARK_MAIN();
