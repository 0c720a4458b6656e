#include "slave/chain.hpp"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include <fmt/format.h>

#include "common/frame_parser.hpp"
#include "slave/firmware.hpp"
#include "slave/frame_tally.hpp"

namespace ecat::slave {

Expected<void, std::string> Chain::add(od::DeviceDescription device, const SlaveOptions& options) {
  return add(std::make_shared<const od::DeviceDescription>(std::move(device)), options);
}

Expected<void, std::string> Chain::add(std::shared_ptr<const od::DeviceDescription> device,
                                       const SlaveOptions& options) {
  auto s = VirtualSlave::create(std::move(device), clock_, options, next_colour());
  if (!s) return fail(s.error());
  segment_.add((*s)->esc());
  slaves_.push_back(std::move(*s));
  added();
  return {};
}

// The next slave's ESC memory colour, from its position
// (esc::EscConfig::memory_colour). An argument, not a copy of the options:
// the copy's temporary allocations moved the slave's objects and, with them,
// the one-drive cycle by 20 % (docs/performance-log.md session 16).
std::uint8_t Chain::next_colour() const noexcept { return esc::EscConfig::memory_colour_at(slaves_.size()); }

void Chain::added() noexcept {
  pending_.resize((slaves_.size() + 63) / 64, 0);
  due_.resize(pending_.size(), 0);
  wakes_.resize(slaves_.size());
  deadlines_.resize(slaves_.size(), Nanoseconds::max());
  small_ = slaves_.size() < kTrackFrom;
  rescan_ = true;
}

bool Chain::process_frame(std::span<std::uint8_t> frame, Nanoseconds now) noexcept {
  const bool returned = pass_frame(frame, now);
  run_firmware(now);
  return returned;
}

Expected<void, std::string> Chain::attach(od::DeviceDescription device, const SlaveOptions& options,
                                          std::size_t parent, unsigned parent_port, unsigned port,
                                          std::optional<Nanoseconds> delay) {
  return attach(std::make_shared<const od::DeviceDescription>(std::move(device)), options, parent, parent_port, port,
                delay);
}

Expected<void, std::string> Chain::attach(std::shared_ptr<const od::DeviceDescription> device,
                                          const SlaveOptions& options, std::size_t parent, unsigned parent_port,
                                          unsigned port, std::optional<Nanoseconds> delay) {
  if (parent >= slaves_.size()) return fail(fmt::format("no slave {} to attach to", parent + 1));
  if (parent_port >= esc::kMaxPorts || port >= esc::kMaxPorts) return fail(std::string("ports are 0..3"));
  if (segment_.peer(parent, parent_port)) {
    return fail(fmt::format("port {} of slave {} is already cabled", parent_port, parent + 1));
  }
  auto s = VirtualSlave::create(std::move(device), clock_, options, next_colour());
  if (!s) return fail(s.error());
  segment_.add((*s)->esc(), parent, parent_port, port, delay);
  slaves_.push_back(std::move(*s));
  added();
  return {};
}

Expected<void, std::string> Chain::connect_redundant(std::size_t slave, unsigned port) {
  if (slave >= slaves_.size() || port >= esc::kMaxPorts) return fail(std::string("no such slave port"));
  if (segment_.peer(slave, port)) return fail(fmt::format("port {} of slave {} is already cabled", port, slave + 1));
  segment_.connect_master(1, slave, port);
  return {};
}

inline void Chain::count_returned(std::span<const std::uint8_t> frame, Nanoseconds now) noexcept {
  const FrameTally t = tally_frame(frame);
  stats_.datagrams += t.datagrams;
  stats_.wkc_total += t.wkc_total;
  if (t.logical) cycle_timing_.on_frame(now, t.first_logical);
}

esc::Delivery Chain::pass_frame_on(std::span<std::uint8_t> frame, Nanoseconds now, unsigned master_port) noexcept {
  seen_ = std::max(seen_, now);
  ++stats_.frames_received;
  const esc::Delivery d = segment_.send(frame, now, master_port);
  if (d.returned()) {
    ++stats_.frames_returned;
    count_returned(frame, now);
  } else if (d.outcome == esc::Delivery::Outcome::Malformed) {
    ++stats_.frames_malformed;
  } else {
    ++stats_.frames_lost;
  }
  return d;
}

void Chain::run_firmware(Nanoseconds now) noexcept {
  // The firmware of a slave reacts to what the frame left behind when its
  // ESC raised the IRQ (or it has work due), as its interrupt handler would
  // within microseconds; the others stay asleep (a few loads each:
  // VirtualSlave::after_frame_due). Only a slave whose ESC a frame entered,
  // a pending one, or - once the time reaches the earliest wake time - any
  // can be due (issue 16 item 5): the others are not asked.
  const std::span<std::uint64_t> entered = segment_.entered();
  if (small_) {  // fewer than kTrackFrom slaves: each one asked (chain.hpp)
    std::fill(entered.begin(), entered.end(), 0);
    for (const auto& s : slaves_) {
      if (s->after_frame_due(now)) s->after_frame(now);
    }
    return;
  }
  DirectNotes notes;
  if (ask_all_ || rescan_) {
    rescanned();
    std::fill(entered.begin(), entered.end(), 0);
    for (std::size_t i = 0; i < slaves_.size(); ++i) {
      after_frame(i, now, notes);
      note(i, notes);  // whatever changed a slave since (set-up, a slave handed out)
    }
    return;
  }
  // The ones whose time came are taken out (after_frame puts them back at
  // their new time), then every candidate once, in order.
  wakes_.take_due(now, due_);
  if (split_ok_ && run_firmware_split(now)) return;
  for (std::size_t w = 0; w < pending_.size(); ++w) {
    std::uint64_t bits = entered[w] | pending_[w] | due_[w];
    entered[w] = 0;
    due_[w] = 0;
    while (bits != 0) {
      const std::size_t i = w * 64 + static_cast<std::size_t>(std::countr_zero(bits));
      bits &= bits - 1;
      after_frame(i, now, notes);
    }
  }
}

void Chain::rescanned() noexcept {
  rescan_ = false;
  split_ok_ = lanes_ && !serial_forced_ && !split_paused_ && slaves_run_apart();
  // A split run lists its words without allocating (slaves may have been
  // added since set_firmware_threads); without room, no split.
  if (split_ok_ && split_words_.capacity() < pending_.size()) {
    try {
      split_words_.reserve(pending_.size());
    } catch (...) {
      split_ok_ = false;
    }
  }
}

template <class Notes>
void Chain::after_frame(std::size_t i, Nanoseconds now, Notes& notes) noexcept {
  VirtualSlave& s = *slaves_[i];
  if (s.after_frame_due(now)) {
    s.after_frame(now);
    note(i, notes);
    return;
  }
  // Not due: not pending; its times are taken again, as the frame may
  // have armed a timer of its ESC (a watchdog, SYNC0).
  if (untracked()) return;
  pending_[i / 64] &= ~(std::uint64_t{1} << (i % 64));
  const Nanoseconds next = s.next_deadline();
  notes.set(*this, i, s.visit_at(), next);
}

template <class Notes>
void Chain::note(std::size_t i, Notes& notes) noexcept {
  if (untracked()) return;
  const VirtualSlave& s = *slaves_[i];
  const std::uint64_t bit = std::uint64_t{1} << (i % 64);
  if (s.pending()) {
    pending_[i / 64] |= bit;
  } else {
    pending_[i / 64] &= ~bit;
  }
  slaves_[i]->esc().take_in_accesses();
  notes.set(*this, i, s.visit_at(), s.next_deadline());
}

// The lanes' forms, called from slave/chain_lanes.cpp.
template void Chain::after_frame<Chain::ApartNotes>(std::size_t, Nanoseconds, ApartNotes&) noexcept;
template void Chain::note<Chain::ApartNotes>(std::size_t, ApartNotes&) noexcept;

void Chain::note_touched() noexcept {
  const std::span<const std::uint64_t> dirty = segment_.dirty();
  const std::span<const std::uint64_t> entered = segment_.entered();
  for (std::size_t w = 0; w < pending_.size(); ++w) {
    for (std::uint64_t bits = dirty[w] | entered[w]; bits != 0; bits &= bits - 1) {
      const std::size_t i = w * 64 + static_cast<std::size_t>(std::countr_zero(bits));
      // Dirty for its own firmware's or poll's accesses only: noted after them.
      if ((entered[w] & (std::uint64_t{1} << (i % 64))) != 0 || slaves_[i]->esc().accessed()) note(i);
    }
  }
}

Nanoseconds Chain::advance(Nanoseconds now) noexcept {
  seen_ = std::max(seen_, now);
  return poll_at(now, true);
}

Nanoseconds Chain::poll_at(Nanoseconds now, bool next) noexcept {
  if (small_ && !poll_all_) {
    // As poll_due, with each slave's visit time read from the slave itself.
    Nanoseconds earliest = kNoDeadline;
    for (const auto& s : slaves_) {
      earliest = std::min(earliest, s->pending() || s->visit_at() <= now ? s->advance(now) : s->next_deadline());
    }
    return earliest;
  }
  return poll_all_ || rescan_ ? poll_every(now) : poll_due(now, next);
}

Nanoseconds Chain::poll_every(Nanoseconds now) noexcept {
  Nanoseconds next = kNoDeadline;
  // Every slave's state moves: what run_firmware keeps is taken anew.
  for (std::size_t i = 0; i < slaves_.size(); ++i) {
    next = std::min(next, slaves_[i]->advance(now));
    note(i);
  }
  rescanned();
  return next;
}

// A slave that is not pending and whose visit time has not come would, if
// polled, run no timer (the ESC's wake bound is later), not run its firmware
// (VirtualSlave::after_frame_due is false, a superset of wants_poll), and
// return its next_deadline(): it is left alone. Its ESC's time of latest
// access (Esc::last_time) is then the last one it had, not `now`.
Nanoseconds Chain::poll_due(Nanoseconds now, bool next) noexcept {
  note_touched();
  wakes_.take_due(now, due_);
  // The polled ones' deadlines are what their polls returned, the others'
  // what they would return: their earliest is poll()'s answer. Then the
  // polled ones are noted as they stand after their firmware ran. Split
  // over the lanes, the two steps are two batches.
  if (Nanoseconds earliest = kNoDeadline; split_ok_ && poll_due_split(now, next, earliest)) return earliest;
  for (std::size_t w = 0; w < pending_.size(); ++w) {
    std::uint64_t bits = pending_[w] | due_[w];
    due_[w] = bits;
    for (; bits != 0; bits &= bits - 1) {
      const std::size_t i = w * 64 + static_cast<std::size_t>(std::countr_zero(bits));
      deadlines_.set(i, slaves_[i]->advance(now));
    }
  }
  const Nanoseconds earliest = next ? deadlines_.earliest() : kNoDeadline;
  for (std::size_t w = 0; w < pending_.size(); ++w) {
    std::uint64_t bits = due_[w];
    due_[w] = 0;
    for (; bits != 0; bits &= bits - 1) note(w * 64 + static_cast<std::size_t>(std::countr_zero(bits)));
  }
  return earliest;
}

Nanoseconds Chain::catch_up(std::optional<Nanoseconds> arrival, Nanoseconds now) noexcept {
  const Nanoseconds latest = std::max(now, seen_);
  const Nanoseconds at = arrival ? std::clamp(*arrival, seen_, latest) : latest;
  seen_ = std::max(seen_, at);
  // Only the timers due by the frame's arrival run first; what poll()
  // would return is not needed here.
  (void)poll_at(at, false);
  return at;
}

std::optional<Nanoseconds> Chain::admit(std::optional<Nanoseconds> arrival, Nanoseconds now) noexcept {
  if (frame_is_stale(arrival, now, max_frame_age_)) {
    ++stats_.frames_stale;
    return std::nullopt;
  }
  return catch_up(arrival, now);
}

Expected<void, std::string> Chain::open_trace(const std::string& path) {
  trace_file_.reset(std::fopen(path.c_str(), "w"));
  if (!trace_file_) return fail(fmt::format("{}: cannot open for writing: {}", path, std::strerror(errno)));
  trace_path_ = path;
  std::vector<std::string> names;
  for (std::size_t i = 0; i < slaves_.size(); ++i) names.push_back(fmt::format("slave{}", i + 1));
  trace_ = std::make_unique<esc::VcdTrace>(trace_file_.get(), names, clock_);
  for (std::size_t i = 0; i < slaves_.size(); ++i) slaves_[i]->attach_trace(trace_->probe(i));
  rescan_ = true;  // the probes write one file: the firmware stays on this thread
  split_ok_ = false;
  return {};
}

Expected<void, std::string> Chain::write_plot(const std::string& path) const {
  // The first drive that records a trace writes it; a failed write is that
  // error (it names the file), never "no trace" (issue 19).
  for (const auto& s : slaves_) {
    Application* app = s->firmware().application();
    if (app && app->has_motion_trace()) return app->write_plot(path);
  }
  return fail(fmt::format("{}: not written: no slave of the chain records a motion trace (a CiA402 drive as the first slave does)", path));
}

Expected<void, std::string> Chain::shutdown() noexcept {
  for (auto& s : slaves_) s->shutdown();
  if (!trace_file_) return {};
  const bool written = trace_->finish();
  // fclose flushes what stdio still holds: its result is the last word.
  const bool closed = std::fclose(trace_file_.release()) == 0;
  if (written && closed) return {};
  try {
    return fail(fmt::format("cannot write {}: {}", trace_path_, std::strerror(errno)));
  } catch (...) {
    return fail(std::string("cannot write the VCD trace"));
  }
}

}  // namespace ecat::slave
