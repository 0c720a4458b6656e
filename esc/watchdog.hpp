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

  // Deadlines off, the timeouts of the reset register values.
  void reset() noexcept;
  // The register values changed (0x0400 divider, 0x0410 PDI time, 0x0420
  // process-data time): the timeouts of the triggers from now on. A running
  // watchdog keeps the deadline of its last trigger, as before the cache.
  void set_times(std::uint16_t divider, std::uint16_t pdi_time, std::uint16_t pd_time) noexcept {
    pd_timeout_ = enabled_timeout(divider, pd_time);
    pdi_timeout_ = enabled_timeout(divider, pdi_time);
  }
  // Restart on a trigger at `now` with the timeouts of set_times: no
  // register is read (the frame of every process-data cycle restarts the
  // watchdog at every drive, and 0x0400 lies on a line nothing else of
  // that frame touches).
  void trigger_process_data(Nanoseconds now) noexcept {
    pd_deadline_ = pd_timeout_ == kNever ? kNever : now + pd_timeout_;  // kNever: time 0, disabled
  }
  void trigger_pdi(Nanoseconds now) noexcept { pdi_deadline_ = pdi_timeout_ == kNever ? kNever : now + pdi_timeout_; }

  // Whether ESC memory shows the running state: 0x0440 bit 0 (process
  // data) and DL status 0x0110 bit 1 (PDI). A trigger writes them only when
  // it does not (after an expiry, a reset or a raw register poke), so the
  // triggers of a running watchdog leave their lines alone.
  bool pd_status_shown() const noexcept { return pd_status_shown_; }
  bool pdi_status_shown() const noexcept { return pdi_status_shown_; }
  void set_status_shown(bool pd, bool pdi) noexcept {
    pd_status_shown_ = pd;
    pdi_status_shown_ = pdi;
  }
  void set_pd_status_shown() noexcept { pd_status_shown_ = true; }
  void set_pdi_status_shown() noexcept { pdi_status_shown_ = true; }

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
  static Nanoseconds enabled_timeout(std::uint16_t divider, std::uint16_t time) noexcept {
    return time == 0 ? kNever : timeout(divider, time);
  }
  Nanoseconds pd_deadline_ = kNever;
  Nanoseconds pdi_deadline_ = kNever;
  Nanoseconds pd_timeout_ = timeout(kWatchdogDividerReset, kWatchdogTimeReset);
  Nanoseconds pdi_timeout_ = timeout(kWatchdogDividerReset, kWatchdogTimeReset);
  bool pd_status_shown_ = true;
  bool pdi_status_shown_ = false;
};

}  // namespace ecat::esc
