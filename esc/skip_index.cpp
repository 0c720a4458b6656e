// The segment's index of passive ESCs (issue 16 item 5): which ESCs a frame
// must enter.
#include "esc/skip_index.hpp"

#include <algorithm>
#include <bit>
#include <numeric>

namespace ecat::esc {

bool SkipIndex::resize(std::size_t n) {
  const std::uint64_t* before = must_.data();
  const std::size_t words = (n + kWordBits - 1) / kWordBits;
  must_.resize(words, 0);
  const std::uint64_t* dirty_before = dirty_.data();
  dirty_.resize(words, 0);
  visit_.resize(words, 0);
  entered_.resize(words, 0);
  next_timer_.resize(n, Nanoseconds::max());
  address_.resize(n, 0);
  first_.resize(n * kSpans, 0);
  end_.resize(n * kSpans, 0);
  order_.resize(n * kSpans, 0);
  sorted_first_.resize(n * kSpans, 0);
  prefix_end_.resize(n * kSpans, 0);
  for (std::size_t i = size_; i < n; ++i) {
    must_[i / kWordBits] |= bit(i);
    entered_[i / kWordBits] |= bit(i);
  }
  size_ = n;
  spans_dirty_ = true;  // every_esc_mapped_ counts the new ones
  return must_.data() != before || dirty_.data() != dirty_before;
}

void SkipIndex::set_spans(std::size_t i, const Spans& spans, std::size_t count) noexcept {
  for (std::size_t k = 0; k < kSpans; ++k) {
    const Span span = k < count ? spans[k] : Span{};
    const std::size_t slot = i * kSpans + k;
    if (first_[slot] != span.first || end_[slot] != span.end) {
      first_[slot] = span.first;
      end_[slot] = span.end;
      spans_dirty_ = true;
    }
  }
}

void SkipIndex::must_visit_all() noexcept { set_every(must_); }

void SkipIndex::all_dirty() noexcept { set_every(dirty_); }

void SkipIndex::entered_all() noexcept { set_every(entered_); }

void SkipIndex::begin_frame() noexcept { std::fill(visit_.begin(), visit_.end(), 0); }

// A linear scan of one word per ESC: station addresses need not be unique
// (all are 0 before the master sets them), and the scan only runs for the
// FPxx of frames that carry no broadcast.
void SkipIndex::mark_address(std::uint16_t adp) noexcept {
  const std::uint32_t* a = address_.data();
  for (std::size_t i = 0; i < size_; ++i) {
    const std::uint32_t v = a[i];
    if ((v & 0xFFFFu) == adp || (v >> 16) == adp) mark(i);
  }
}

void SkipIndex::rebuild_spans() noexcept {
  spans_ = 0;
  std::size_t mapped = 0;  // ESCs with a span (an ESC's slots are i * kSpans + k, in a row)
  std::size_t last_esc = size_;
  for (std::size_t slot = 0; slot < size_ * kSpans; ++slot) {
    if (first_[slot] >= end_[slot]) continue;
    order_[spans_++] = static_cast<std::uint32_t>(slot);
    if (slot / kSpans != last_esc) {
      last_esc = slot / kSpans;
      ++mapped;
    }
  }
  std::sort(order_.begin(), order_.begin() + static_cast<std::ptrdiff_t>(spans_),
            [&](std::uint32_t a, std::uint32_t b) { return first_[a] < first_[b] || (first_[a] == first_[b] && a < b); });
  std::uint64_t reach = 0;
  for (std::size_t k = 0; k < spans_; ++k) {
    sorted_first_[k] = first_[order_[k]];
    reach = std::max(reach, end_[order_[k]]);
    prefix_end_[k] = reach;
  }
  hull_first_ = spans_ > 0 ? sorted_first_[0] : 0;
  hull_end_ = reach;
  every_esc_mapped_ = size_ > 0 && mapped == size_;
  spans_dirty_ = false;
}

// The spans that start before the datagram's end, walked down from the
// last one while some span among the rest still reaches past its start:
// for the disjoint spans of a process image, the ESCs the datagram maps and
// one more compare (Esc::process_logical makes the same test per ESC).
void SkipIndex::mark_logical(std::uint64_t first, std::size_t size) noexcept {
  if (size == 0) return;
  if (spans_dirty_) rebuild_spans();
  const std::uint64_t last = first + size;
  std::size_t k = static_cast<std::size_t>(
      std::lower_bound(sorted_first_.begin(), sorted_first_.begin() + static_cast<std::ptrdiff_t>(spans_), last) -
      sorted_first_.begin());
  while (k > 0) {
    --k;
    if (prefix_end_[k] <= first) break;
    const std::uint32_t slot = order_[k];
    if (end_[slot] > first) mark(slot / kSpans);
  }
}

std::size_t SkipIndex::spans_starting_in(std::uint64_t first, std::size_t size) noexcept {
  if (spans_dirty_) rebuild_spans();
  const auto begin = sorted_first_.begin();
  const auto end = begin + static_cast<std::ptrdiff_t>(spans_);
  const auto from = std::lower_bound(begin, end, first);
  return static_cast<std::size_t>(std::lower_bound(from, end, first + size) - from);
}

void SkipIndex::mark_due(Nanoseconds start, Nanoseconds hop) noexcept {
  if (size_ == 0 || min_timer_ > start + hop * static_cast<std::int64_t>(size_ - 1)) return;
  Nanoseconds earliest = Nanoseconds::max();
  for (std::size_t i = 0; i < size_; ++i) {
    if ((must_[i / kWordBits] & bit(i)) != 0) continue;  // entered anyway; its timer is read again then
    if (next_timer_[i] <= start + hop * static_cast<std::int64_t>(i)) {
      must_[i / kWordBits] |= bit(i);
    } else {
      earliest = std::min(earliest, next_timer_[i]);
    }
  }
  min_timer_ = earliest;
}

void SkipIndex::mark_due_at(Nanoseconds start, const Nanoseconds* unit_at, Nanoseconds none,
                            Nanoseconds last) noexcept {
  if (size_ == 0 || min_timer_ > start + last) return;
  Nanoseconds earliest = Nanoseconds::max();
  for (std::size_t i = 0; i < size_; ++i) {
    if ((must_[i / kWordBits] & bit(i)) != 0) continue;  // entered anyway; its timer is read again then
    if (unit_at[i] != none && next_timer_[i] <= start + unit_at[i]) {
      must_[i / kWordBits] |= bit(i);
    } else {
      earliest = std::min(earliest, next_timer_[i]);
    }
  }
  min_timer_ = earliest;
}

}  // namespace ecat::esc
