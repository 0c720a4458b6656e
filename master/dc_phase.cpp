// DC phase lock of the master's cycle; the model and its choices are in
// dc_phase.hpp and docs/dc.md ("The master's cycle locked to SYNC0").
#include "master/dc_phase.hpp"

#include <algorithm>
#include <cmath>

namespace ecat::master {
namespace {

// Renormalise the fractional offset into the integer base beyond this (ns),
// so the double keeps sub-ns resolution whatever the system time's size.
constexpr double kRebaseAbove = 1e6;

std::int64_t floor_div(std::int64_t a, std::int64_t b) noexcept {
  const std::int64_t q = a / b;
  return (a % b != 0 && ((a < 0) != (b < 0))) ? q - 1 : q;
}

}  // namespace

std::int64_t DcPhaseLock::offset_at(Nanoseconds local) const noexcept {
  const double ahead = drift_ * static_cast<double>((local - t_last_).count());
  return base_ + std::llround(delta_ + ahead);
}

// Index n of the first SYNC0 (start + n * cycle) strictly after `system_time`.
std::int64_t DcPhaseLock::sync0_index_after(std::uint64_t system_time) const noexcept {
  const auto rel = static_cast<std::int64_t>(system_time - c_.sync0_start);  // 64-bit wrap safe
  return floor_div(rel, c_.cycle.count()) + 1;
}

Nanoseconds DcPhaseLock::next_send(Nanoseconds now) noexcept {
  if (frames_ == 0) return now + c_.cycle;
  const std::int64_t offset = offset_at(now);
  const auto system_now = static_cast<std::uint64_t>(now.count() + offset);
  std::int64_t n = sync0_index_after(system_now + static_cast<std::uint64_t>(c_.guard.count()));
  if (last_target_) n = std::max(n, *last_target_ + 1);
  last_target_ = n;
  const std::uint64_t sync0 = c_.sync0_start + static_cast<std::uint64_t>(n * c_.cycle.count());
  const auto send_system = static_cast<std::int64_t>(sync0 - static_cast<std::uint64_t>(c_.lead.count()));
  // The offset at the send time itself (the drift over the wait, 80 ns at
  // 80 ppm and 1 ms): a second pass from the first guess.
  const Nanoseconds guess{send_system - offset};
  const Nanoseconds send{send_system - offset_at(guess)};
  return std::max(send, now);
}

void DcPhaseLock::update(Nanoseconds sent_at, std::uint64_t reference_time) noexcept {
  const std::int64_t sample = static_cast<std::int64_t>(reference_time) - sent_at.count();
  if (frames_ < c_.acquire_frames) {
    // Acquisition: the smallest (system - local) of the first frames is the
    // one least delayed between the clock read and the wire.
    if (frames_ == 0 || sample < offset_at(sent_at)) {
      base_ = sample;
      delta_ = 0;
    } else {
      delta_ += drift_ * static_cast<double>((sent_at - t_last_).count());
    }
    drift_ = 0;
  } else {
    const double predicted_delta = delta_ + drift_ * static_cast<double>((sent_at - t_last_).count());
    double e = static_cast<double>(sample - base_) - predicted_delta;
    const auto clamp = static_cast<double>(c_.max_step.count());
    e = std::clamp(e, -clamp, clamp);
    delta_ = predicted_delta + c_.kp * e;
    drift_ += c_.ki * e / static_cast<double>(c_.cycle.count());
  }
  if (std::abs(delta_) > kRebaseAbove) {
    const auto whole = static_cast<std::int64_t>(delta_);
    base_ += whole;
    delta_ -= static_cast<double>(whole);
  }
  t_last_ = sent_at;
  ++frames_;

  const std::int64_t fed = sync0_index_after(reference_time);
  // SYNC0 events exist from index 0 (the start time) on.
  if (last_index_) {
    const std::int64_t first_unfed = std::max<std::int64_t>(*last_index_ + 1, 0);
    if (fed > first_unfed) missed_ += static_cast<std::uint64_t>(fed - first_unfed);
  }
  if (!last_index_ || fed > *last_index_) last_index_ = fed;
  last_target_ = last_target_ ? std::max(*last_target_, fed) : fed;
  const std::uint64_t sync0 = c_.sync0_start + static_cast<std::uint64_t>(fed * c_.cycle.count());
  margin_ = static_cast<std::int64_t>(sync0 - reference_time);
  const std::int64_t cycle = c_.cycle.count();
  std::int64_t err = c_.lead.count() - margin_;  // later than aimed: smaller margin
  err = ((err % cycle) + cycle + cycle / 2) % cycle - cycle / 2;
  phase_error_ = err;
}

}  // namespace ecat::master
