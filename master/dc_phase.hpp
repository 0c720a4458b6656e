// The master's cycle locked to the DC system time (issue 19): the cyclic
// frame reaches the reference clock a fixed `lead` before each SYNC0, whatever
// the phase at which the master started and however its own clock drifts
// against the reference.
//
// Why: a DC slave in Sync0 mode latches its outputs at SYNC0 and counts a
// SYNC0 without a new SM2 buffer since the previous one as a missed SM event
// (ETG.1020 1C32h:0Bh; docs/dc.md). A master whose cycle has an arbitrary
// phase to SYNC0 has an arbitrary margin, 0 to one cycle, for its own
// lateness; at half a cycle before SYNC0 it has half a cycle either way.
// TwinCAT sends its frame a configurable shift before SYNC0; SOEM's ec_sample
// steers its wake-up with a PI loop on (DC time - syncoffset) mod cycle
// (masters.md). This is the same idea with an explicit model:
//
//   system time (at the reference) = local time + offset + drift * (t - t0)
//
// estimated from each cyclic frame: the FRMW 0x0910:8 it carries returns the
// reference's system time when the frame passed it (esc-registers.md §10),
// compared with the local time the frame was sent. The estimate is an
// alpha-beta (PI) filter: offset += kp * e, drift += ki * e / cycle, with
// e = measured - predicted, clamped to +/- max_step once locked (a frame that
// was sent late after its time stamp, e.g. a preemption between the clock
// read and the send, is one outlier and moves the estimate by at most
// kp * max_step). The constant part of the wire time ends in the offset, so
// what is locked is the arrival at the reference, not the send.
//
// From the estimate, the frame for SYNC0 number n (system time start + n *
// cycle, 0x0990/0x09A0 as configure_sync0 wrote them) is sent at the local
// time where the system time is start + n * cycle - lead. After a stall the
// next frame goes to the first SYNC0 still at least `guard` ahead: at once if
// that SYNC0's send time has passed, else at its send time; never two frames
// for one SYNC0.
//
// Time is injected: next_send() takes `now`, update() takes the measured
// pair, nothing here sleeps or reads a clock (tests/master/dc_phase_test.cpp
// runs it on simulated time).
#pragma once

#include <cstdint>
#include <optional>

#include "common/clock.hpp"

namespace ecat::master {

struct DcPhaseConfig {
  Nanoseconds cycle{1'000'000};          // SYNC0 cycle (0x09A0)
  Nanoseconds lead{500'000};             // frame at the reference this long before SYNC0
  std::uint64_t sync0_start = 0;         // system time of the first SYNC0 (0x0990)
  double kp = 0.1;                       // alpha: share of the error taken into the offset per frame
  double ki = 0.0025;                    // beta: share taken into the drift (critically damped with kp = 0.1)
  Nanoseconds max_step{20'000};          // error clamp once locked
  Nanoseconds guard{50'000};             // a SYNC0 closer than this to now is not aimed at
  unsigned acquire_frames = 8;           // frames whose smallest (system - local) sets the first offset
};

class DcPhaseLock {
 public:
  explicit DcPhaseLock(DcPhaseConfig config) noexcept : c_(config) {}

  // Local time at which to send the frame for the next SYNC0 that is still at
  // least `guard` ahead of `now` (at most `now` itself when its send time has
  // passed). Before the first update() there is no estimate: now + cycle.
  Nanoseconds next_send(Nanoseconds now) noexcept;

  // One cyclic frame: sent at local time `sent_at`, passed the reference when
  // its system time was `reference_time` (the FRMW 0x0910 read-back).
  void update(Nanoseconds sent_at, std::uint64_t reference_time) noexcept;

  // Arrival of the last frame at the reference relative to its target
  // (SYNC0 - lead), wrapped into [-cycle/2, cycle/2): positive = later than
  // aimed. 0 before the first update.
  std::int64_t phase_error() const noexcept { return phase_error_; }
  // Time from the last frame's arrival at the reference to the next SYNC0.
  std::int64_t margin_to_sync0() const noexcept { return margin_; }
  // SYNC0 events that passed with no frame arriving since the SYNC0 before
  // them, as seen from the reference's time stamps: what a slave in Sync0
  // mode counts as missed SM events (1C32h:0Bh), counted from the second
  // update on.
  std::uint64_t sync0_without_frame() const noexcept { return missed_; }
  // Frames used so far; acquisition ends after acquire_frames.
  std::uint64_t frames() const noexcept { return frames_; }
  bool acquired() const noexcept { return frames_ >= c_.acquire_frames; }
  // The current estimate of (system time - local time) at `local`.
  std::int64_t offset_at(Nanoseconds local) const noexcept;
  double drift() const noexcept { return drift_; }

 private:
  std::int64_t sync0_index_after(std::uint64_t system_time) const noexcept;

  DcPhaseConfig c_;
  std::int64_t base_ = 0;      // integer part of the offset (first acquisition sample)
  double delta_ = 0;           // offset - base_, ns
  double drift_ = 0;           // ns per ns
  Nanoseconds t_last_{0};      // local time of the last update
  std::uint64_t frames_ = 0;
  std::optional<std::int64_t> last_index_;  // SYNC0 the last frame fed
  std::optional<std::int64_t> last_target_;  // SYNC0 index the last frame was for
  std::int64_t phase_error_ = 0;
  std::int64_t margin_ = 0;
  std::uint64_t missed_ = 0;
};

}  // namespace ecat::master
