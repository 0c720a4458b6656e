// What a line segment knows of each of its ESCs to let a frame pass the ones
// it does not address (issue 16 item 5; docs/esc.md "Skipping ESCs a frame
// does not address"). Kept outside the Escs, one compact array per field,
// so deciding which ESCs a frame must enter reads a few words per datagram
// instead of every ESC's cache lines.
//
// An ESC is "passive" when a frame that does not address it changes nothing
// in it but its times (esc/pass_hook.hpp): port 0 open and the frame going
// on out of port 1, no IRQ field to OR into the datagrams, no DC receive
// latch armed, no timer due, the fast paths on. The index keeps, per ESC,
// that state as the ESC showed it when a frame last entered it, and a
// "must visit" bit for every ESC that is not passive or was accessed since
// (PDI, poll, link: Esc::touch sets the bit). For each frame the segment
// then enters the ESCs with the bit, the ones a datagram addresses - by
// position (APxx: the ADP it has at that ESC), station address or alias
// (FPxx), or the logical span of its FMMUs (LRD/LWR/LRW) - and the ones
// whose timer falls due while the frame passes.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <span>
#include <vector>

#include "common/clock.hpp"

namespace ecat::esc {

class SkipIndex {
 public:
  static constexpr std::size_t kWordBits = 64;
  static constexpr std::size_t kSpans = 4;
  struct Span {
    std::uint64_t first = 0;
    std::uint64_t end = 0;
    bool operator==(const Span&) const = default;
  };

  // What the segment read of ESC i after a frame entered it.
  struct Passive {
    bool passive = false;
    Nanoseconds next_timer = Nanoseconds::max();
    std::uint16_t station = 0;
    std::uint16_t alias = 0;  // = station while the alias is not enabled (0x0100 bit 24)
  };
  using Spans = std::array<Span, kSpans>;

  // Set-up: room for `n` ESCs (the new ones must be visited). Returns true
  // when the must-visit words moved (the hooks pointing into them must be set again).
  bool resize(std::size_t n);
  std::size_t size() const noexcept { return size_; }
  std::uint64_t* dirty_word(std::size_t i) noexcept { return &dirty_[i / kWordBits]; }
  // The ESCs accessed from outside a frame since (Esc::touch): the segment
  // reads them again (update) before the next frame.
  std::span<std::uint64_t> dirty_words() noexcept { return dirty_; }
  static std::uint64_t bit(std::size_t i) noexcept { return std::uint64_t{1} << (i % kWordBits); }

  // After a frame entered ESC i, or it was accessed from outside a frame.
  void update(std::size_t i, const Passive& p) noexcept {
    std::uint64_t& w = must_[i / kWordBits];
    if (!p.passive) {
      w |= bit(i);
      return;
    }
    w &= ~bit(i);
    next_timer_[i] = p.next_timer;
    min_timer_ = std::min(min_timer_, p.next_timer);
    address_[i] = p.station | (std::uint32_t{p.alias} << 16);
  }

  // The logical bytes ESC i's active FMMUs map, as up to kSpans disjoint
  // [first, end) ranges by start (more are joined into the last one): not
  // the one range over all of them (Esc::logical_first_/end_), which for a
  // drive with outputs and inputs spans the images of all slaves between.
  void set_spans(std::size_t i, const Spans& spans, std::size_t count) noexcept;
  // Every ESC must be visited (a frame went round the port walk).
  void must_visit_all() noexcept;
  // Every ESC is to be read again before the next frame that skips.
  void all_dirty() noexcept;
  // Whether logical bytes [first, first + size) meet a span of every ESC:
  // each has one and all lie inside (the plan would mark every ESC).
  bool maps_every_esc(std::uint64_t first, std::size_t size) noexcept {
    if (spans_dirty_) rebuild_spans();
    return every_esc_mapped_ && first <= hull_first_ && first + size >= hull_end_;
  }
  // How many spans start inside logical bytes [first, first + size): about
  // the ESCs the datagram maps (two binary searches, whatever the count; an
  // ESC with two spans inside counts twice, one whose span starts before
  // `first` not at all).
  // Out of line: the frames that never ask (FPxx, BRD) keep their path.
  std::size_t spans_starting_in(std::uint64_t first, std::size_t size) noexcept;

  // --- One frame ---
  void begin_frame() noexcept;
  // FPxx with ADP `adp`: every ESC with that station address or enabled alias.
  void mark_address(std::uint16_t adp) noexcept;
  // ESC i (an APxx whose ADP reaches 0 there).
  void mark(std::size_t i) noexcept { visit_[i / kWordBits] |= bit(i); }
  // LRD/LWR/LRW over logical bytes [first, first + size).
  void mark_logical(std::uint64_t first, std::size_t size) noexcept;
  // ESCs whose own timer falls due when the frame reaches them (start + i x hop).
  void mark_due(Nanoseconds start, Nanoseconds hop) noexcept;
  // The same on a tree or ring: ESC i's processing unit has the frame at
  // start + unit_at[i] (`none`: it does not; `last`: the latest of them).
  void mark_due_at(Nanoseconds start, const Nanoseconds* unit_at, Nanoseconds none, Nanoseconds last) noexcept;
  // The first ESC >= i the frame must enter, or size().
  std::size_t next(std::size_t i) const noexcept {
    std::size_t w = i / kWordBits;
    if (w >= must_.size()) return size_;
    std::uint64_t bits = (must_[w] | visit_[w]) & (~std::uint64_t{0} << (i % kWordBits));
    for (;;) {
      if (bits != 0) return std::min(size_, w * kWordBits + static_cast<std::size_t>(std::countr_zero(bits)));
      if (++w >= must_.size()) return size_;
      bits = must_[w] | visit_[w];
    }
  }


  // ESCs a frame entered since the last take_entered() (bit i: ESC i):
  // the slave layer runs the firmware of these only (slave::Chain).
  void entered(std::size_t i) noexcept { entered_[i / kWordBits] |= bit(i); }
  // ESCs 0 .. count - 1 (a frame that entered every ESC up to one).
  void entered_first(std::size_t count) noexcept { set_first(entered_.data(), count); }
  void entered_all() noexcept;
  std::span<std::uint64_t> entered_words() noexcept { return entered_; }

 private:
  void rebuild_spans() noexcept;
  // Sets bits 0 .. count - 1 of `words`, a whole word at a time.
  static void set_first(std::uint64_t* words, std::size_t count) noexcept {
    for (; count >= kWordBits; count -= kWordBits) *words++ = ~std::uint64_t{0};
    if (count != 0) *words |= (std::uint64_t{1} << count) - 1;
  }
  void set_every(std::vector<std::uint64_t>& words) const noexcept { set_first(words.data(), size_); }

  std::size_t size_ = 0;
  std::vector<std::uint64_t> must_;
  std::vector<std::uint64_t> dirty_;
  std::vector<std::uint64_t> visit_;
  std::vector<std::uint64_t> entered_;
  std::vector<Nanoseconds> next_timer_;
  std::vector<std::uint32_t> address_;  // station | alias << 16
  std::vector<std::uint64_t> first_;  // kSpans per ESC: slot i * kSpans + k
  std::vector<std::uint64_t> end_;
  // The non-empty span slots by start; prefix_end_[k]: the largest end
  // among order_[0..k] (a query walks down from its end).
  std::vector<std::uint32_t> order_;
  std::vector<std::uint64_t> sorted_first_;
  std::vector<std::uint64_t> prefix_end_;
  std::size_t spans_ = 0;
  bool spans_dirty_ = false;
  // Over all spans (rebuild_spans): the lowest start, the highest end, and
  // whether every ESC has at least one.
  std::uint64_t hull_first_ = 0;
  std::uint64_t hull_end_ = 0;
  bool every_esc_mapped_ = false;
  // No passive ESC's timer is due before this (a lower bound; mark_due
  // scans only when a frame reaches it).
  Nanoseconds min_timer_ = Nanoseconds::min();
};

}  // namespace ecat::esc
