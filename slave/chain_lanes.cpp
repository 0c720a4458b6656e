// slave::Chain's firmware lanes (issue 30 item 3, set_firmware_threads):
// the candidates of a firmware run or a due poll split over the threads by
// 64-slave words. In a file of its own: the one-thread path in chain.cpp
// keeps its code as it was (docs/performance-log.md "Firmware lanes").
#include <algorithm>
#include <bit>

#include <fmt/format.h>

#include "slave/chain.hpp"

namespace ecat::slave {

// Out of line, so that the one-thread loop of run_firmware keeps its
// registers (with this inline, `entered` went to the stack).
bool Chain::run_firmware_split(Nanoseconds now) noexcept {
  const std::span<std::uint64_t> entered = segment_.entered();
  // Only the pending and the timed ones count towards a split: a slave a
  // frame merely entered is mostly not due (a broadcast enters them all),
  // and its few loads cost more on another core than here.
  std::size_t busy = 0;
  for (std::size_t w = 0; w < pending_.size(); ++w) {
    busy += static_cast<std::size_t>(std::popcount(due_[w] | pending_[w]));
    due_[w] |= entered[w] | pending_[w];
    entered[w] = 0;
  }
  if (!plan_split(busy)) return false;  // the loop takes the merged candidates
  run_lanes(&Chain::run_word, now);
  return true;
}

bool Chain::poll_due_split(Nanoseconds now, bool next, Nanoseconds& earliest) noexcept {
  std::size_t busy = 0;
  for (std::size_t w = 0; w < pending_.size(); ++w) {
    due_[w] |= pending_[w];
    busy += static_cast<std::size_t>(std::popcount(due_[w]));
  }
  if (!plan_split(busy)) return false;
  run_lanes(&Chain::poll_word, now);
  earliest = next ? deadlines_.earliest() : kNoDeadline;
  run_lanes(&Chain::note_word, now);
  return true;
}

// The candidates of each word go to one lane: the word's pending bit, the
// segment's entered and dirty bits (Esc::touch) of its slaves are written
// by that lane alone, their wake times and deadlines are their own entries
// (WakeTimes::set_apart), and the bounds are merged in run_lanes.
bool Chain::plan_split(std::size_t busy) noexcept {
  if (busy < min_split_) return false;
  split_words_.clear();  // reserved: no allocation
  for (std::size_t w = 0; w < due_.size(); ++w) {
    if (due_[w] != 0) split_words_.push_back(static_cast<std::uint32_t>(w));
  }
  return split_words_.size() >= 2;
}

void Chain::run_lanes(SpinWorkers::Task task, Nanoseconds now) noexcept {
  for (ApartNotes& n : lane_notes_) n.wake_bound = n.deadline_bound = WakeTimes::Bound{};
  split_now_ = now;
  lanes_->run(task, this, split_words_.size());
  for (const ApartNotes& n : lane_notes_) {
    wakes_.merge(n.wake_bound);
    deadlines_.merge(n.deadline_bound);
  }
  ++split_runs_;
}

// The lanes' tasks, each over the candidates of word split_words_[k] (due_).
void Chain::run_word(void* chain, std::size_t k, unsigned lane) noexcept {
  Chain& c = *static_cast<Chain*>(chain);
  const std::size_t w = c.split_words_[k];
  std::uint64_t bits = c.due_[w];
  c.due_[w] = 0;
  for (; bits != 0; bits &= bits - 1) {
    c.after_frame(w * 64 + static_cast<std::size_t>(std::countr_zero(bits)), c.split_now_, c.lane_notes_[lane]);
  }
}

void Chain::poll_word(void* chain, std::size_t k, unsigned lane) noexcept {
  Chain& c = *static_cast<Chain*>(chain);
  const std::size_t w = c.split_words_[k];
  for (std::uint64_t bits = c.due_[w]; bits != 0; bits &= bits - 1) {
    const std::size_t i = w * 64 + static_cast<std::size_t>(std::countr_zero(bits));
    c.deadlines_.set_apart(i, c.slaves_[i]->advance(c.split_now_), c.lane_notes_[lane].deadline_bound);
  }
}

void Chain::note_word(void* chain, std::size_t k, unsigned lane) noexcept {
  Chain& c = *static_cast<Chain*>(chain);
  const std::size_t w = c.split_words_[k];
  std::uint64_t bits = c.due_[w];
  c.due_[w] = 0;
  for (; bits != 0; bits &= bits - 1) c.note(w * 64 + static_cast<std::size_t>(std::countr_zero(bits)), c.lane_notes_[lane]);
}

void Chain::pause_split(bool paused) noexcept {
  if (paused == split_paused_) return;
  split_paused_ = paused;
  if (paused) {
    split_ok_ = false;
  } else {
    rescan_ = true;  // rescanned() decides split_ok_ and reserves the word list's room
  }
}

bool Chain::slaves_run_apart() const noexcept {
  return std::all_of(slaves_.begin(), slaves_.end(), [](const auto& s) { return s->runs_apart(); });
}

Expected<void, std::string> Chain::set_firmware_threads(unsigned threads, std::size_t min_slaves) {
  if (threads == 0) return fail(std::string("firmware threads: at least 1"));
  lanes_.reset();
  split_ok_ = false;
  min_split_ = min_slaves;
  if (threads == 1) return {};
  try {
    lane_notes_.assign(threads, ApartNotes{});
    lanes_ = std::make_unique<SpinWorkers>(threads - 1);
  } catch (const std::exception& e) {
    return fail(fmt::format("firmware threads: cannot start {} helper threads: {}", threads - 1, e.what()));
  }
  rescan_ = true;  // split_ok_ is decided, and the word list's room reserved, at the rescan (rescanned)
  return {};
}

}  // namespace ecat::slave
