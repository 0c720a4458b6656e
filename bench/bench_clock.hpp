// The simulated clock of the benches' drive lines (bench/drive_line.hpp):
// ManualClock's time, and on demand the cost of a live run's clock. In a
// live run every read of the slaves' clock (SteadyClock, CLOCK_MONOTONIC)
// costs a call into the vDSO, ~30 ns on the 2-vCPU VM of docs/performance.md;
// the simulated clock costs a load. With live_reads on, each read also reads
// the host's steady clock and throws it away, so a case pays what
// ecat-slave's live loop pays while the simulation keeps its own, exact
// time, and the reads are counted (reads_per_drive in bench_cycle).
#pragma once

#include <chrono>
#include <cstdint>

#include "common/clock.hpp"

namespace ecat::bench {

class BenchClock final : public Clock {
 public:
  Nanoseconds now() const noexcept override {
    if (live_reads_) [[unlikely]] {
      ++reads_;
      (void)std::chrono::steady_clock::now();
    }
    return now_;
  }
  void set(Nanoseconds t) noexcept { now_ = t; }
  void live_reads(bool on) noexcept { live_reads_ = on; }
  std::uint64_t reads() const noexcept { return reads_; }

 private:
  Nanoseconds now_{0};
  bool live_reads_ = false;
  mutable std::uint64_t reads_ = 0;
};

}  // namespace ecat::bench
