// Injected time (STYLE lesson 10): nothing inside the stack reads the system
// clock or sleeps. Tests use ManualClock; programs use SteadyClock.
#pragma once

#include <chrono>
#include <cstdint>

namespace ecat {

// Nanoseconds since an arbitrary epoch fixed for the life of a clock.
using Nanoseconds = std::chrono::nanoseconds;

class Clock {
 public:
  virtual ~Clock() = default;
  virtual Nanoseconds now() const noexcept = 0;
};

// Simulated time, moved only by the test or simulator that owns it.
class ManualClock final : public Clock {
 public:
  explicit ManualClock(Nanoseconds start = Nanoseconds{0}) noexcept : now_(start) {}
  Nanoseconds now() const noexcept override { return now_; }
  void advance(Nanoseconds d) noexcept { now_ += d; }
  void set(Nanoseconds t) noexcept { now_ = t; }

 private:
  Nanoseconds now_;
};

// CLOCK_MONOTONIC, for live runs.
class SteadyClock final : public Clock {
 public:
  Nanoseconds now() const noexcept override {
    return std::chrono::duration_cast<Nanoseconds>(
        std::chrono::steady_clock::now().time_since_epoch());
  }
};

}  // namespace ecat
