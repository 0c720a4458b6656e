// ESC watchdogs (Section I §10, Section II 0x0400-0x0443;
// shared/spec/esc-registers.md §8): a divider turning 40 ns ticks into the
// watchdog base unit, the PDI watchdog (restarted by PDI accesses) and the
// process-data watchdog (restarted by ECAT writes to SMs with control bit 6).
// Expiry is evaluated on the injected time.
#pragma once

#include <cstdint>
#include <optional>

#include "common/clock.hpp"

namespace ecat::esc {

inline constexpr std::uint16_t kWatchdogDividerReset = 0x09C2;  // 2498 -> 100 µs
inline constexpr std::uint16_t kWatchdogTimeReset = 0x03E8;     // 1000 units -> 100 ms
inline constexpr std::int64_t kEscClockPeriodNs = 40;           // 25 MHz
inline constexpr std::uint16_t kWatchdogDividerOffset = 2;      // divider = ticks - 2

class Watchdogs {
 public:
  // Timeout for a time register value under `divider` (0 = disabled).
  static Nanoseconds timeout(std::uint16_t divider, std::uint16_t time) noexcept {
    const std::int64_t unit = (static_cast<std::int64_t>(divider) + kWatchdogDividerOffset) * kEscClockPeriodNs;
    return Nanoseconds{unit * time};
  }

  void reset() noexcept;
  // Restart on a trigger at `now` with the current register values.
  void trigger_process_data(Nanoseconds now, std::uint16_t divider, std::uint16_t time) noexcept {
    pd_deadline_ = time == 0 ? kNever : now + timeout(divider, time);  // 0 = disabled
  }
  void trigger_pdi(Nanoseconds now, std::uint16_t divider, std::uint16_t time) noexcept {
    pdi_deadline_ = time == 0 ? kNever : now + timeout(divider, time);  // 0 = disabled
  }

  // Fault injection: a running process-data watchdog expires at `now`, as
  // if no trigger had come for its whole time. False (and nothing changes)
  // when it is not running (disabled, or not triggered since it expired).
  bool expire_process_data(Nanoseconds now) noexcept {
    if (pd_deadline_ == kNever) return false;
    pd_deadline_ = now;
    return true;
  }

  struct Expired {
    bool process_data = false;
    bool pdi = false;
  };
  // Reports (once each) the watchdogs that expired by `now`.
  Expired check(Nanoseconds now) noexcept;
  std::optional<Nanoseconds> next_deadline() const noexcept {
    const Nanoseconds t = earliest();
    if (t == kNever) return std::nullopt;
    return t;
  }
  // The same as one compare: Nanoseconds::max() when neither is armed.
  Nanoseconds earliest() const noexcept { return pd_deadline_ < pdi_deadline_ ? pd_deadline_ : pdi_deadline_; }

 private:
  // Deadlines stored as plain times (no std::optional on the per-frame
  // path); kNever = not armed.
  static constexpr Nanoseconds kNever = Nanoseconds::max();
  Nanoseconds pd_deadline_ = kNever;
  Nanoseconds pdi_deadline_ = kNever;
};

}  // namespace ecat::esc
