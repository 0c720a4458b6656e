#include "control/simulated_run.hpp"

#include "slave/chain.hpp"

namespace ecat::control {

SimulatedRun::SimulatedRun(ManualClock& clock, slave::Chain& chain, Nanoseconds period, Cycle cycle)
    : clock_(clock), chain_(chain), period_(period), cycle_(std::move(cycle)) {}

void SimulatedRun::step(std::uint64_t cycles) {
  for (std::uint64_t i = 0; i < cycles; ++i) {
    clock_.advance(period_);
    (void)chain_.poll(clock_.now());
    if (cycle_) cycle_(clock_.now());
    ++cycles_;
  }
}

bool SimulatedRun::tick() {
  if (paused_) return false;
  step(1);
  return true;
}

}  // namespace ecat::control
