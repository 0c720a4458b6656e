// The CiA 402 drive's own application cycle (issue 8), without the ESC, CoE
// or object binding: one ds402::Drive (the generic servo, default plant) in
// CSP at 1 kHz, stepped once per iteration, and its Plant alone.
//   Drive_CspHold  holding the position where it was enabled (the case of
//                  bench_cycle's drives);
//   Drive_CspMove  following a moving CSP set-point: a back-and-forth
//                  trapezoid of 100 ms ramps to 1000 rpm and 800 ms at speed
//                  (2000 cycles a period, +-15 revolutions), so most cycles
//                  move at constant speed and some accelerate or reverse;
//   Plant_Hold / Plant_Move  the same two demands given to Plant::step
//                  directly (position loop, velocity PI, torque lag, load);
//   Plant_MoveJitter  the move with a cycle time jittering by +-1 us;
//   Plant_HoldAfterMove  holding where one leg of the move ended.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "bench/bench_options.hpp"
#include "ds402/drive.hpp"

namespace ecat::bench {
namespace {

using namespace std::chrono_literals;

constexpr Nanoseconds kCycle = 1ms;
constexpr double kCycleS = 1e-3;
constexpr std::uint16_t kShutdown = 0x0006, kSwitchOn = 0x0007, kEnableOperation = 0x000F;
constexpr std::uint16_t kStateMask = 0x006F, kOperationEnabled = 0x0027;
constexpr std::int8_t kModeCsp = 8;
constexpr int kRampCycles = 100;    // 0 -> top speed
constexpr int kCruiseCycles = 800;  // at top speed
constexpr double kTopRpm = 1000;

// One period of the moving set-point (increments, one value per cycle): out
// and back, so it can repeat for any number of iterations.
std::vector<std::int32_t> move_profile(std::uint32_t resolution) {
  const double top = kTopRpm * resolution / 60.0;  // increments/s
  const double acc = top / (kRampCycles * kCycleS);
  std::vector<std::int32_t> out;
  double pos = 0, v = 0;
  for (const double dir : {1.0, -1.0}) {
    for (int i = 0; i < 2 * kRampCycles + kCruiseCycles; ++i) {
      const double a = i < kRampCycles ? acc : (i < kRampCycles + kCruiseCycles ? 0.0 : -acc);
      const double v_next = v + dir * a * kCycleS;
      pos += (v + v_next) / 2 * kCycleS;
      v = v_next;
      out.push_back(static_cast<std::int32_t>(std::lround(pos)));
    }
    v = 0;
  }
  return out;
}

struct EnabledDrive {
  ds402::DriveInputs in;
  ds402::DriveOutputs out;
  ds402::Drive drive{ds402::generic_drive(), ds402::PlantParameters{}};

  EnabledDrive() {
    in.modes_of_operation = kModeCsp;
    drive.step(in, out, kCycle);  // transition 1: Not ready -> Switch on disabled
    for (std::uint16_t cw : {kShutdown, kSwitchOn, kEnableOperation}) {
      in.controlword = cw;
      drive.step(in, out, kCycle);
    }
  }
  bool enabled() const { return (out.statusword & kStateMask) == kOperationEnabled; }
};

void check_enabled(benchmark::State& state, const EnabledDrive& d) {
  if (!d.enabled()) {
    const std::string why = "drive not in operation enabled: statusword " + std::to_string(d.out.statusword) +
                            " error " + std::to_string(d.out.error_code);
    state.SkipWithError(why.c_str());
  }
}

void BM_Drive_CspHold(benchmark::State& state) {
  EnabledDrive d;
  check_enabled(state, d);
  for (auto _ : state) {
    d.drive.step(d.in, d.out, kCycle);
    benchmark::DoNotOptimize(d.out.position_actual);
  }
  check_enabled(state, d);
}
BENCHMARK(BM_Drive_CspHold)->Apply(iterations_from_env);

void BM_Drive_CspMove(benchmark::State& state) {
  EnabledDrive d;
  const std::vector<std::int32_t> profile = move_profile(ds402::PlantParameters{}.encoder_resolution);
  std::size_t k = 0;
  check_enabled(state, d);
  for (auto _ : state) {
    d.in.target_position = profile[k];
    k = k + 1 == profile.size() ? 0 : k + 1;
    d.drive.step(d.in, d.out, kCycle);
    benchmark::DoNotOptimize(d.out.position_actual);
  }
  check_enabled(state, d);
  state.counters["following_error"] = static_cast<double>(d.out.following_error);
}
BENCHMARK(BM_Drive_CspMove)->Apply(iterations_from_env);

// The plant alone: position demand and limits as the drive gives them in CSP.
ds402::LoopLimits default_limits(const ds402::PlantParameters& p) {
  ds402::LoopLimits lim;
  lim.torque_positive = lim.torque_negative = p.peak_torque;
  lim.velocity = p.max_speed * p.encoder_resolution / 60.0;
  return lim;
}

void BM_Plant_Hold(benchmark::State& state) {
  const ds402::PlantParameters p;
  ds402::Plant plant(p);
  const ds402::LoopLimits lim = default_limits(p);
  ds402::LoopDemand demand{ds402::LoopDemand::Kind::Position, plant.position(), 0, 0, 0};
  for (auto _ : state) {
    plant.step(demand, lim, kCycleS);
    benchmark::DoNotOptimize(plant.position());
  }
}
BENCHMARK(BM_Plant_Hold)->Apply(iterations_from_env);

// The plant following the move profile; with `jitter` the cycle time
// varies by +-1 us, as a free-running loop timed by the real clock sees it:
// the closed form is not rebuilt for each new cycle time, the sub-steps run
// (bench_cycle's clock is exact).
void run_plant_move(benchmark::State& state, bool jitter) {
  const ds402::PlantParameters p;
  ds402::Plant plant(p);
  const ds402::LoopLimits lim = default_limits(p);
  const std::vector<std::int32_t> profile = move_profile(p.encoder_resolution);
  std::size_t k = 0;
  double last = plant.position();
  for (auto _ : state) {
    const double target = profile[k];
    const double dt =
        jitter ? kCycleS + static_cast<double>(static_cast<int>((k * 7919) % 201) - 100) * 1e-8 : kCycleS;
    k = k + 1 == profile.size() ? 0 : k + 1;
    plant.step(ds402::LoopDemand{ds402::LoopDemand::Kind::Position, target, (target - last) / dt, 0, 0}, lim, dt);
    last = target;
    benchmark::DoNotOptimize(plant.position());
  }
}

void BM_Plant_Move(benchmark::State& state) { run_plant_move(state, false); }
BENCHMARK(BM_Plant_Move)->Apply(iterations_from_env);

void BM_Plant_MoveJitter(benchmark::State& state) { run_plant_move(state, true); }
BENCHMARK(BM_Plant_MoveJitter)->Apply(iterations_from_env);

// Holding after a move: the rotor stopped next to the target, friction
// holds it while the velocity integral unwinds (the usual state of a drive
// that has arrived).
void BM_Plant_HoldAfterMove(benchmark::State& state) {
  const ds402::PlantParameters p;
  ds402::Plant plant(p);
  const ds402::LoopLimits lim = default_limits(p);
  const std::vector<std::int32_t> profile = move_profile(p.encoder_resolution);
  double last = plant.position();
  for (std::size_t k = 0; k < profile.size() / 2 + 1000; ++k) {  // out, then 1 s standing
    const double target = profile[std::min(k, profile.size() / 2 - 1)];
    plant.step(ds402::LoopDemand{ds402::LoopDemand::Kind::Position, target, (target - last) / kCycleS, 0, 0}, lim,
               kCycleS);
    last = target;
  }
  const ds402::LoopDemand hold{ds402::LoopDemand::Kind::Position, last, 0, 0, 0};
  for (auto _ : state) {
    plant.step(hold, lim, kCycleS);
    benchmark::DoNotOptimize(plant.position());
  }
  state.counters["standstill"] = plant.last_path() == ds402::Plant::Path::Standstill;
}
BENCHMARK(BM_Plant_HoldAfterMove)->Apply(iterations_from_env);

}  // namespace
}  // namespace ecat::bench

BENCHMARK_MAIN();
