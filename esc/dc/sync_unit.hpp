// The SYNC0/SYNC1 generator of a DC unit (ESC datasheet Section I §9.2.4
// "SyncSignal generation", Section II 0x0980-0x09A7; esc-registers.md §10).
// Works in this ESC's system time (local time + offset): pulses fall at
// start time + k * SYNC0 cycle; SYNC1 either mirrors SYNC0 (cycle 0), is
// shifted from each SYNC0 (cycle < SYNC0 cycle) or fires with the first SYNC0
// at least `SYNC1 cycle` after the previous SYNC1 (a multiple of SYNC0).
#pragma once

#include <cstdint>
#include <optional>

namespace ecat::esc {

struct SyncSettings {
  std::uint8_t activation = 0;     // 0x0981
  std::uint64_t start_time = 0;    // 0x0990
  std::uint32_t sync0_cycle = 0;   // 0x09A0; 0 = single shot
  std::uint32_t sync1_cycle = 0;   // 0x09A4
};

class SyncUnit {
 public:
  // Near future for the plausibility check (0x0981 bit 6 = 1), ~2.1 s.
  static constexpr std::uint64_t kNearFutureShort = 1ull << 31;
  static constexpr std::uint64_t kNearFutureLong = 1ull << 63;  // half the 64-bit range
  // Catch-up limit per advance(): after this many pulses the rest are skipped.
  static constexpr unsigned kMaxPulsesPerAdvance = 1000;

  struct Pulse {
    unsigned signal;       // 0 = SYNC0, 1 = SYNC1
    std::uint64_t time;    // scheduled system time
  };
  // Receives each pulse as advance() generates it.
  class Sink {
   public:
    virtual ~Sink() = default;
    virtual void pulse(const Pulse& p) noexcept = 0;
  };

  void reset() noexcept;
  // 0x0981 written with bit 0 = 1 (or auto-activation by a 0x0990 write):
  // arms the generator at system time `now`.
  void activate(const SyncSettings& s, std::uint64_t now) noexcept;
  void deactivate() noexcept;
  // One pulse now on the enabled outputs (0x0981 bit 7).
  void debug_pulse(std::uint64_t now, Sink& sink) noexcept;

  // Generates every pulse due up to system time `now`; returns the system
  // time of the next pulse, if any.
  std::optional<std::uint64_t> advance(std::uint64_t now, Sink& sink) noexcept;

  bool active() const noexcept { return active_; }
  // A pulse is scheduled: advance() has something to do at some time.
  bool pulse_pending() const noexcept { return next0_.has_value() || next1_.has_value(); }
  std::uint8_t activation_status() const noexcept { return status_; }
  // 0x0990 read: next SYNC0 time while active, else the programmed start.
  std::uint64_t next_sync0() const noexcept;
  // 0x0998: next SYNC1 time (0 if none).
  std::uint64_t next_sync1() const noexcept;

 private:
  void sync0_tick(std::uint64_t t, Sink& sink) noexcept;
  bool sync0_out() const noexcept;
  bool sync1_out() const noexcept;

  SyncSettings s_{};
  bool active_ = false;
  std::optional<std::uint64_t> next0_;
  std::optional<std::uint64_t> next1_;
  std::uint64_t sync1_anchor_ = 0;  // SYNC0 time SYNC1 counts its cycle from
  std::uint8_t status_ = 0;
};

}  // namespace ecat::esc
