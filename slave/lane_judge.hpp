// --firmware-threads auto while the chain runs (issue 30 item 3): whether
// the firmware runs split over the two threads is judged again, from time
// to time, by what each way costs on this host now. The start's choice
// (slave/lane_choice.hpp) rests on one core-to-core round trip, and this
// VM's vCPUs move: 90 ns in one run, 383-416 ns minutes later (docs/
// performance-log.md "Session 19: --firmware-threads auto"), where two threads
// take 1.4-2.4x the wall time of one. A run that outlives such a move
// would keep the wrong way.
//
// A trial is three windows of equal length, A B A: the way in force, the
// other way, the way in force again. Its figure per window is the mean
// wall time the chain's firmware took per frame (Chain::run_firmware after
// the frame and the due polls before the next one: the work the lanes
// split). The other way is taken when its mean is at most `gain` times the
// mean of the two A windows: the A B A order cancels a load that rises or
// falls steadily over the trial, and the margin keeps a noisy host from
// switching back and forth. No verdict when a window saw fewer than
// `min_frames` frames that took less than half of it (a master that
// stopped or paused; a way so slow that its frames fill the window counts
// with fewer: two threads on one CPU took 7.5 ms a frame), or when no run
// was split in the split windows (the chain's busy slaves were too few to
// split: both ways ran the same code).
//
// The frames and times are the same either way (Chain::pause_split); only
// the wall time moves. Time is injected: `now` of every sample.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "common/clock.hpp"

namespace ecat::slave {

class LaneJudge {
 public:
  struct Settings {
    // From the end of one trial (or the start) to the next trial.
    Nanoseconds every = std::chrono::seconds(10);
    // Each of a trial's three windows.
    Nanoseconds window = std::chrono::milliseconds(500);
    std::uint32_t min_frames = 100;
    // The other way must take at most this fraction of the way in force.
    double gain = 0.9;
    // The trial of the other way ends at once when its frames have taken
    // more than this many times what the first window spent in as long
    // (in at least a tenth of a window, so that one heavy frame at its
    // start is no reason), or, from its give_up_frames-th frame and a
    // tenth of a window on, more than this many times the first window's
    // mean per frame (a master whose frames thin out as each takes
    // longer): a way that is much
    // dearer (a helper whose CPU something else took: 37-70x here) would
    // otherwise hold up the master's frames for a whole window.
    double give_up = 1.5;
    std::uint32_t give_up_frames = 10;
  };

  // What a trial found: each window's mean per frame (ns) and frames.
  struct Trial {
    bool split_before = false;  // the way in force during the trial
    double before_ns = 0;
    double other_ns = 0;
    double after_ns = 0;
    std::uint32_t frames_before = 0;
    std::uint32_t frames_other = 0;
    std::uint32_t frames_after = 0;
    bool decided = false;  // false: no verdict (see `reason`)
    bool given_up = false;  // the other way's window was ended early (see give_up)
    bool switched = false;
    std::string reason;  // the verdict in words
  };

  // `split`: the way the chain starts with (the start's choice).
  LaneJudge(bool split, Nanoseconds start, Settings settings);
  LaneJudge(bool split, Nanoseconds start) : LaneJudge(split, start, Settings{}) {}

  // The way the chain is to run now: split over the lanes or not.
  bool split() const noexcept { return trying() ? !in_force_ : in_force_; }

  // One frame's firmware took `busy` (wall time) at `now`, the way split()
  // said; `split_ran`: at least one of its runs was split. Returns true when
  // split() changed (the caller pauses or resumes the chain's split).
  // Allocates only when a trial ends (its reason).
  bool add(Nanoseconds now, Nanoseconds busy, bool split_ran);

  // Whether the next add() at `now` begins a trial. Before a trial of two
  // threads the caller may look at the host first (ecat-slave measures the
  // cores' round trip: a helper that cannot run would stall the frames of
  // the whole trial) and skip_trial(): no trial until a period later, the
  // reason kept as the last trial's.
  bool trial_due(Nanoseconds now) const noexcept {
    return phase_ == Phase::Steady && now - phase_start_ >= settings_.every;
  }
  void skip_trial(Nanoseconds now, std::string reason);

  // Trials ended (with or without a verdict, skipped ones too) and switches made.
  std::uint32_t trials() const noexcept { return trials_; }
  std::uint32_t switches() const noexcept { return switches_; }
  const std::optional<Trial>& last_trial() const noexcept { return last_; }

 private:
  enum class Phase : std::uint8_t { Steady, Before, Other, After };
  struct Window {
    Nanoseconds busy{0};
    std::uint32_t frames = 0;
    std::uint32_t split_frames = 0;
    double mean() const noexcept { return frames == 0 ? 0.0 : static_cast<double>(busy.count()) / frames; }
  };
  bool trying() const noexcept { return phase_ == Phase::Other; }
  // Moves to `next` at `now`, with an empty window.
  void enter(Phase next, Nanoseconds now) noexcept;
  // Counts the trial `t`, takes the other way if it says so, and waits a period.
  void end_trial(Trial t, Nanoseconds now);
  Trial verdict() const;
  // In the other way's window: whether it has already cost too much (give_up).
  bool too_dear(Nanoseconds now) const noexcept;
  void give_up(Nanoseconds now);

  Settings settings_;
  bool in_force_;
  Phase phase_ = Phase::Steady;
  Nanoseconds phase_start_;
  Nanoseconds last_sample_;
  Window current_;
  Window before_;
  Window other_;
  std::uint32_t trials_ = 0;
  std::uint32_t switches_ = 0;
  std::optional<Trial> last_;
};

}  // namespace ecat::slave
