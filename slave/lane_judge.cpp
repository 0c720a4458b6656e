#include "slave/lane_judge.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace ecat::slave {
namespace {

constexpr double kNsPerUs = 1000.0;
constexpr double kNsPerMs = 1000.0 * kNsPerUs;
// too_dear: the least part of a window the other way is allowed the first
// window's time for, and the least it runs before its mean per frame counts.
constexpr double kLeastShare = 0.1;

const char* threads_of(bool split) noexcept { return split ? "2 threads" : "1 thread"; }

}  // namespace

LaneJudge::LaneJudge(bool split, Nanoseconds start, Settings settings)
    : settings_(settings), in_force_(split), phase_start_(start), last_sample_(start) {}

void LaneJudge::enter(Phase next, Nanoseconds now) noexcept {
  phase_ = next;
  phase_start_ = now;
  current_ = Window{};
}

bool LaneJudge::add(Nanoseconds now, Nanoseconds busy, bool split_ran) {
  const bool was_split = split();
  // Frames that stopped for longer than a window in the middle of a trial
  // (a master that paused): its windows no longer compare like with like.
  if (phase_ != Phase::Steady && now - last_sample_ > settings_.window) {
    skip_trial(now, fmt::format("no verdict: no frame for {:.1f} ms during the trial",
                                static_cast<double>((now - last_sample_).count()) / kNsPerMs));
  }
  last_sample_ = now;
  if (phase_ == Phase::Steady) {
    if (now - phase_start_ >= settings_.every) enter(Phase::Before, now);
    return split() != was_split;
  }
  current_.busy += busy;
  ++current_.frames;
  if (split_ran) ++current_.split_frames;
  if (phase_ == Phase::Other && too_dear(now)) {
    give_up(now);
    return split() != was_split;
  }
  if (now - phase_start_ < settings_.window) return split() != was_split;
  switch (phase_) {
    case Phase::Before:
      before_ = current_;
      enter(Phase::Other, now);
      break;
    case Phase::Other:
      other_ = current_;
      enter(Phase::After, now);
      break;
    case Phase::After:
      end_trial(verdict(), now);
      break;
    case Phase::Steady:
      break;
  }
  return split() != was_split;
}

void LaneJudge::skip_trial(Nanoseconds now, std::string reason) {
  Trial t;
  t.split_before = in_force_;
  t.reason = std::move(reason);
  end_trial(std::move(t), now);
}

void LaneJudge::end_trial(Trial t, Nanoseconds now) {
  ++trials_;
  if (t.switched) {
    in_force_ = !in_force_;
    ++switches_;
  }
  last_ = std::move(t);
  enter(Phase::Steady, now);
}

bool LaneJudge::too_dear(Nanoseconds now) const noexcept {
  const double elapsed = static_cast<double>((now - phase_start_).count()) / static_cast<double>(settings_.window.count());
  const double share = std::max(kLeastShare, elapsed);
  if (static_cast<double>(current_.busy.count()) > settings_.give_up * static_cast<double>(before_.busy.count()) * share) {
    return true;
  }
  // Per frame only over a tenth of a window at least: a master's cycle of
  // several frames, one of them carrying every drive's application cycle,
  // makes the mean of a few frames swing.
  return elapsed >= kLeastShare && current_.frames >= settings_.give_up_frames &&
         current_.mean() > settings_.give_up * before_.mean();
}

void LaneJudge::give_up(Nanoseconds now) {
  Trial t;
  t.split_before = in_force_;
  t.before_ns = before_.mean();
  t.other_ns = current_.mean();
  t.frames_before = before_.frames;
  t.frames_other = current_.frames;
  t.decided = true;
  t.given_up = true;
  t.reason = fmt::format("{} took {:.1f} us in {} frame(s) ({:.1f} ms into its trial), more than {}x what {} took "
                         "in as long or per frame: trial ended early, stays on {}",
                         threads_of(!in_force_), static_cast<double>(current_.busy.count()) / kNsPerUs,
                         current_.frames, static_cast<double>((now - phase_start_).count()) / kNsPerMs,
                         settings_.give_up, threads_of(in_force_), threads_of(in_force_));
  end_trial(std::move(t), now);
}

LaneJudge::Trial LaneJudge::verdict() const {
  Trial t;
  t.split_before = in_force_;
  t.before_ns = before_.mean();
  t.other_ns = other_.mean();
  t.after_ns = current_.mean();
  t.frames_before = before_.frames;
  t.frames_other = other_.frames;
  t.frames_after = current_.frames;
  // A window counts with min_frames frames, or with fewer when they took
  // half of it or more: a way that slow is measured well enough (two
  // threads on one CPU: 66 frames in 500 ms, 7.5 ms each).
  const auto counts = [&](const Window& w) { return w.frames >= settings_.min_frames || 2 * w.busy >= settings_.window; };
  for (const Window* w : {&before_, &other_, &current_}) {
    if (!counts(*w)) {
      t.reason = fmt::format("no verdict: {} frame(s) in a window, fewer than {}", w->frames, settings_.min_frames);
      return t;
    }
  }
  // The split windows: the other one when 1 thread is in force, else both A windows.
  const bool any_split = in_force_ ? before_.split_frames + current_.split_frames > 0 : other_.split_frames > 0;
  if (!any_split) {
    t.reason = "no verdict: no run was split (too few slaves busy at once): both ways ran the same";
    return t;
  }
  t.decided = true;
  const double reference = (t.before_ns + t.after_ns) / 2;
  t.switched = t.other_ns <= settings_.gain * reference;
  t.reason = fmt::format("{:.1f} us per frame on {} against {:.1f} us on {} (its windows {:.1f} and {:.1f}): {}",
                         t.other_ns / kNsPerUs, threads_of(!in_force_), reference / kNsPerUs, threads_of(in_force_),
                         t.before_ns / kNsPerUs, t.after_ns / kNsPerUs,
                         t.switched ? fmt::format("now {}", threads_of(!in_force_))
                                    : fmt::format("stays on {}", threads_of(in_force_)));
  return t;
}

}  // namespace ecat::slave
