// Simulated time for an in-process network (issue 26 item 1): a chain on a
// ManualClock and the master's cycle, advanced one cycle at a time. The
// control interface pauses it, steps N cycles and runs it again; the
// owner's loop calls tick(), which runs a cycle unless paused. Nothing here
// sleeps: a test on simulated time stays deterministic.
//
//   ManualClock clock;
//   slave::Chain chain(clock);  ... add slaves ...
//   control::SimulatedRun sim(clock, chain, 1ms, [&](Nanoseconds now) { master.cycle(now); });
//   control::RequestHandler handler(chain, events, nullptr, &sim);
//   while (...) { sim.tick(); server.service(clock.now()); }
#pragma once

#include <cstdint>
#include <functional>

#include "common/clock.hpp"

namespace ecat::slave {
class Chain;
}

namespace ecat::control {

class SimulatedRun {
 public:
  // What a cycle does after time moved on: usually the master's frames
  // through the chain (Chain::process_frame). May be empty: then a cycle
  // only runs the slaves' timers and firmware.
  using Cycle = std::function<void(Nanoseconds now)>;

  SimulatedRun(ManualClock& clock, slave::Chain& chain, Nanoseconds period, Cycle cycle = {});

  bool paused() const noexcept { return paused_; }
  void pause() noexcept { paused_ = true; }
  void run() noexcept { paused_ = false; }
  // Runs `cycles` cycles now, paused or not: each moves the clock on by one
  // period, runs the chain's timers (Chain::poll), then the cycle.
  void step(std::uint64_t cycles);
  // One cycle unless paused; true when it ran.
  bool tick();

  std::uint64_t cycles() const noexcept { return cycles_; }
  Nanoseconds period() const noexcept { return period_; }
  Nanoseconds now() const noexcept { return clock_.now(); }

 private:
  ManualClock& clock_;
  slave::Chain& chain_;
  Nanoseconds period_;
  Cycle cycle_;
  bool paused_ = false;
  std::uint64_t cycles_ = 0;
};

}  // namespace ecat::control
