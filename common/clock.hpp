// Injected time (STYLE lesson 10): nothing inside the stack reads the system
// clock or sleeps. Tests use ManualClock; programs use SteadyClock.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

namespace ecat {

// Nanoseconds since an arbitrary epoch fixed for the life of a clock.
using Nanoseconds = std::chrono::nanoseconds;

// "No deadline" where a function on the cyclic path returns a time instead
// of a std::optional<Nanoseconds> (issue 30): GCC builds such an optional on
// the stack with two narrow stores and reads its flag back as one 8-byte
// load, which the CPU cannot forward from the 1-byte store - a stall of
// some 15 cycles at every return. The public polls wrap these inline.
inline constexpr Nanoseconds kNoDeadline = Nanoseconds::max();
constexpr std::optional<Nanoseconds> deadline_or_none(Nanoseconds t) noexcept {
  return t == kNoDeadline ? std::nullopt : std::optional<Nanoseconds>(t);
}

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
