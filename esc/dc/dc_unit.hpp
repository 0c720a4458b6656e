// Distributed-clocks unit of one ESC with 64-bit DC: registers 0x0900-0x09FF
// (ESC datasheet Section I §9, Section II §10; shared/spec/esc-registers.md
// §10). The Esc routes every access in that block here, with the simulated
// (true) time of the access: for ECAT accesses the time the frame started
// passing this ESC (SOF at port 0), for PDI accesses the clock's now.
//   - local clock with its own ppm error (LocalClock), system time = local + 0x0920
//   - receive-time latches on an ECAT write to 0x0900 (ports 0..3, 0x0918)
//   - 0x0910 ECAT read: system time at SOF minus 0x0928 (time the frame passed
//     the reference clock); ECAT write: one comparison for the time loop
//   - SYNC0/SYNC1 generation (SyncUnit) and two LATCH inputs (LatchUnit)
// Behaviour choices are in docs/dc.md.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>

#include "common/clock.hpp"
#include "esc/access_side.hpp"
#include "esc/dc/latch_unit.hpp"
#include "esc/dc/local_clock.hpp"
#include "esc/dc/sync_unit.hpp"
#include "esc/dc/time_loop.hpp"

namespace ecat::esc {

// Told of SYNC and LATCH edges as they happen (application trigger, VCD trace).
class DcObserver {
 public:
  virtual ~DcObserver() = default;
  // SYNC0 (signal 0) or SYNC1 (signal 1) output changes to `level` at true time t.
  virtual void on_sync(unsigned signal, bool level, Nanoseconds t) noexcept = 0;
};

class DcUnit : private SyncUnit::Sink {
 public:
  static constexpr std::uint16_t kSize = 0x0100;  // 0x0900..0x09FF
  static constexpr unsigned kPorts = 4;
  static constexpr unsigned kSyncSignals = 2;
  static constexpr unsigned kLatchInputs = 2;
  static constexpr std::uint64_t kPulseLengthUnitNs = 10;  // 0x0982 unit

  // `offset` is relative to 0x0900; offset + size <= kSize (the Esc clips).
  void read(std::uint16_t offset, std::span<std::uint8_t> out, Nanoseconds t,
            Side side = Side::Ecat) noexcept;
  void write(std::uint16_t offset, std::span<const std::uint8_t> in, Nanoseconds t,
             Side side = Side::Ecat) noexcept;
  // The same for an ECAT write of the system time 0x0910 alone, 4 or 8
  // bytes from its start (the ARMW/FRMW of every DC cycle at each ESC but
  // the reference): the time loop's comparison, nothing stored.
  void write_system_time(std::span<const std::uint8_t> in, Nanoseconds t) noexcept {
    last_t_ = std::max(last_t_, t);
    if (active()) wake_ = Nanoseconds::min();  // as write()
    compare_system_time(in, t);
  }
  // A frame reached `port` at time t (before the ESC processes it for port 0,
  // on its way back for the other ports). Inline: every frame calls it; the
  // receive times are stored only after a write to 0x0900 armed the latch.
  void on_frame_arrival(int port, Nanoseconds t) noexcept {
    if (t > last_t_) last_t_ = t;
    if (port <= 0) {
      receive_latch_armed_ = false;  // a new frame
      return;
    }
    if (receive_latch_armed_ && port < static_cast<int>(kPorts)) latch_return_time(port, t);
  }
  // A frame reached `port` (1..3) before this ESC's processing unit (it
  // entered from port 1..3 and a closed port turned it into the processing
  // unit: the far end of a ring). Kept so that a 0x0900 write later in the
  // same frame latches it (Section II 0x0900: the receive time at every
  // port of the latching frame). begin_frame() forgets the last frame's.
  void on_arrival_before_processing(int port, Nanoseconds t) noexcept {
    if (t > last_t_) last_t_ = t;
    if (port <= 0 || port >= static_cast<int>(kPorts)) return;
    early_[static_cast<unsigned>(port)] = t;
    early_mask_ = static_cast<std::uint8_t>(early_mask_ | (1u << port));
  }
  void begin_frame() noexcept { early_mask_ = 0; }
  // A frame passed this ESC by without addressing it (issue 16 item 5:
  // esc::Segment skips it and the ESC catches up later): only the latest
  // time seen moves. Only valid while no receive latch is armed.
  void note_time(Nanoseconds t) noexcept {
    if (t > last_t_) last_t_ = t;
  }
  // A write to 0x0900 armed the receive-time latch; the next frame's
  // arrival at port 0 disarms it.
  bool receive_latch_armed() const noexcept { return receive_latch_armed_; }
  // Advances SYNC generation to `now`; returns when it next needs to run.
  std::optional<Nanoseconds> poll(Nanoseconds now) noexcept { return deadline_or_none(advance(now)); }
  // The same as a time, kNoDeadline when none (Esc::advance's form).
  Nanoseconds advance(Nanoseconds now) noexcept;
  // A pulse scheduled or an output high: poll() has something to do.
  bool active() const noexcept { return sync_.pulse_pending() || sync_level_[0] || sync_level_[1]; }
  // A time before which poll() does nothing (Nanoseconds::max(): never):
  // the deadline the last poll() returned (none: no pulse scheduled, no
  // output high) - unless anything since could have moved it earlier (a
  // register write, which may also change the clock through the time loop,
  // a reset, a clock fault), then Nanoseconds::min(). A read only lowers an
  // output (acknowledge mode): the bound stays a bound. A slave::Chain polls
  // only the slaves whose time came (docs/e2e.md "Live timing").
  Nanoseconds wake_bound() const noexcept { return wake_; }

  // Event bits the unit currently requests: AL event request 0x0220 bits
  // 1..3 (latch, SYNC0, SYNC1) and ECAT event request 0x0210 bit 0 (latch).
  // The Esc ORs them into its event registers.
  std::uint32_t al_event_request() const noexcept { return al_events_; }
  std::uint16_t ecat_event_request() const noexcept { return ecat_events_; }

  // Power-on/ESC reset; `sync_pulse_length` is SII word 2 (-> 0x0982).
  // The oscillator (set_clock) keeps running.
  void reset(std::uint16_t sync_pulse_length) noexcept;

  // --- Simulation and application side (additive to the Esc interface) ---
  // Oscillator error and local time at true time 0 (set-up).
  void set_clock(double ppm, std::uint64_t start) noexcept {
    clock_.reset(ppm, start);
    wake_ = Nanoseconds::min();
  }
  const LocalClock& clock() const noexcept { return clock_; }
  std::uint64_t local_time(Nanoseconds t) const noexcept { return clock_.at(t); }
  std::uint64_t system_time(Nanoseconds t) const noexcept { return clock_.at(t) + offset(); }
  // True time at which this ESC's system time reaches `system`.
  Nanoseconds when_system(std::uint64_t system) const noexcept { return clock_.when(system - offset()); }
  // LATCH0/1 pin goes to `level` at true time t.
  void set_latch_input(unsigned unit, bool level, Nanoseconds t) noexcept;
  // Current SYNC0/SYNC1 output level (as of the last poll/read).
  bool sync_output(unsigned signal) const noexcept { return sync_level_[signal]; }
  void set_observer(DcObserver* observer) noexcept { observer_ = observer; }
  const TimeLoop& time_loop() const noexcept { return loop_; }

  // --- Faults (slave::FaultCatalogue, docs/faults.md "DC") ---
  // The oscillator runs `ppm` off from true time t on (the ESC's own error;
  // the time loop's correction stays as it is), or its local time steps by
  // `ns` at t: what the time loop then compares shows it in 0x092C.
  void set_oscillator_ppm(Nanoseconds t, double ppm) noexcept {
    clock_.set_ppm(t, ppm);
    wake_ = Nanoseconds::min();
  }
  void jump_local_time(Nanoseconds t, std::int64_t ns) noexcept {
    clock_.jump(t, ns);
    wake_ = Nanoseconds::min();
  }
  // SYNC0 stopped: the unit keeps its schedule (0x0981, 0x0990 as they
  // were) but no SYNC0 pulse reaches the output or AL event bit 2.
  void inhibit_sync0(bool on) noexcept { sync0_inhibited_ = on; }
  bool sync0_inhibited() const noexcept { return sync0_inhibited_; }

 private:
  void pulse(const SyncUnit::Pulse& p) noexcept override;
  // Bytes [first, end) of the block as a read at `t` sees them into the same
  // places of `view`; a register partly inside may write its other bytes too.
  void render(std::span<std::uint8_t, kSize> view, Nanoseconds t, Side side, std::uint16_t first,
              std::uint16_t end) const noexcept;
  void after_read(std::uint16_t first, std::uint16_t end, Side side, Nanoseconds t) noexcept;
  bool writable(std::uint16_t offset, Side side) const noexcept;
  void after_write(std::uint16_t first, std::uint16_t end, Nanoseconds t) noexcept;
  void latch_receive_times(Nanoseconds t) noexcept;
  void latch_return_time(int port, Nanoseconds t) noexcept;
  void compare_system_time(std::span<const std::uint8_t> written, Nanoseconds t) noexcept;
  void activation_written(Nanoseconds t) noexcept;
  void start_time_written(std::uint16_t first, std::uint16_t end, Nanoseconds t) noexcept;
  void set_sync_level(unsigned signal, bool level, Nanoseconds t) noexcept;
  // The same at the true time this ESC's system time reaches `system`.
  void set_sync_level_at_system(unsigned signal, bool level, std::uint64_t system) noexcept;
  static bool touches_high(std::uint16_t first, std::uint16_t end) noexcept;
  void end_pulses(std::uint64_t system_now) noexcept;
  void update_latch_events() noexcept;
  std::uint64_t offset() const noexcept;
  std::uint32_t delay() const noexcept;
  bool acknowledge_mode() const noexcept;

  std::array<std::uint8_t, kSize> regs_{};  // stored (written/latched) values
  std::array<LatchUnit, kLatchInputs> latches_{};
  std::array<std::uint64_t, kSyncSignals> pulse_end_{};  // system time, pulse mode
  DcObserver* observer_ = nullptr;
  // Arrivals before the processing unit (on_arrival_before_processing):
  // only frames of a port walk write them, so they stay off the per-frame lines.
  std::array<Nanoseconds, kPorts> early_{};
  std::uint8_t early_mask_ = 0;  // bit n: early_[n] holds this frame's arrival at port n
  // What a DC cycle reads (the system-time comparison, the SYNC timing),
  // then what every frame reads or writes (on_frame_arrival, the Esc's IRQ
  // field), last: the Esc keeps its own per-frame members right behind
  // (issue 30 item 1: a drive's DC unit in four lines a cycle, not six).
  LocalClock clock_;
  TimeLoop loop_;
  SyncUnit sync_;
  std::array<bool, kSyncSignals> sync_level_{};
  std::uint32_t al_events_ = 0;
  std::uint16_t ecat_events_ = 0;
  // Latest time a frame, a register access or a latch input showed the
  // unit (not a poll: a reset anchors the clock's correction at it, and a
  // chain polls only the slaves whose time came).
  Nanoseconds last_t_{0};
  Nanoseconds wake_ = Nanoseconds::max();  // wake_bound()'s
  // Last: next to the Esc members esc::Segment's skip index reads with it.
  bool receive_latch_armed_ = false;
  bool sync0_inhibited_ = false;  // fault: SYNC0 pulses suppressed
};

}  // namespace ecat::esc
