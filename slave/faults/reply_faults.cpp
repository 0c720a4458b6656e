#include "slave/faults/reply_faults.hpp"

#include <algorithm>
#include <cstring>

namespace ecat::slave::faults {

void ReplyFaults::add(const ReplyRule& r) {
  rules_.push_back(r);
  spent_.reserve(rules_.size());
  outbox_.resize(kOutboxFrames);
}

bool ReplyFaults::remove(ReplyFaultId id) noexcept {
  const std::size_t n = rules_.size();
  std::erase_if(rules_, [id](const ReplyRule& r) { return r.id == id; });
  return rules_.size() != n;
}

bool ReplyFaults::hold(std::span<const std::uint8_t> frame, unsigned master_port, Nanoseconds due) noexcept {
  if (frame.size() > kMaxFrame) return false;
  for (Slot& s : outbox_) {
    if (s.used) continue;
    std::memcpy(s.bytes.data(), frame.data(), frame.size());
    s.length = frame.size();
    s.master_port = master_port;
    s.due = due;
    s.order = next_order_++;
    s.used = true;
    return true;
  }
  ++overflowed_;
  return false;
}

void ReplyFaults::remember(std::span<const std::uint8_t> frame, unsigned master_port) noexcept {
  if (frame.size() > kMaxFrame) {
    have_previous_ = false;
    return;
  }
  std::memcpy(previous_.bytes.data(), frame.data(), frame.size());
  previous_.length = frame.size();
  previous_.master_port = master_port;
  have_previous_ = true;
}

bool ReplyFaults::after_return(std::span<const std::uint8_t> frame, unsigned master_port, Nanoseconds now) noexcept {
  bool withheld = false;
  for (ReplyRule& r : rules_) {
    if (!r.until_cleared && r.left == 0) continue;  // spent, waiting to be cleared
    // Replay needs a reply before this one: the first frame it sees goes
    // out as it is (and is the one replayed next), without counting.
    if (r.kind == ReplyRule::Kind::Replay && !have_previous_) break;
    switch (r.kind) {
      case ReplyRule::Kind::Delay:
        (void)hold(frame, master_port, now + r.delay);  // a full outbox loses it (counted)
        withheld = true;
        break;
      case ReplyRule::Kind::Duplicate:
        (void)hold(frame, master_port, now);
        break;
      case ReplyRule::Kind::Replay:
        // The reply before this one goes out in its place.
        (void)hold({previous_.bytes.data(), previous_.length}, previous_.master_port, now);
        withheld = true;
        break;
    }
    if (!r.until_cleared && --r.left == 0) spent_.push_back(r.id);
    break;  // one rule per frame: the first engaged
  }
  remember(frame, master_port);
  return withheld;
}

std::optional<ReplyFaults::Due> ReplyFaults::take_due(Nanoseconds now, std::span<std::uint8_t> out) noexcept {
  Slot* first = nullptr;
  for (Slot& s : outbox_) {
    if (!s.used || s.due > now) continue;
    if (!first || s.due < first->due || (s.due == first->due && s.order < first->order)) first = &s;
  }
  if (!first || out.size() < first->length) return std::nullopt;
  std::memcpy(out.data(), first->bytes.data(), first->length);
  first->used = false;
  return Due{first->length, first->master_port};
}

std::optional<Nanoseconds> ReplyFaults::next_due() const noexcept {
  std::optional<Nanoseconds> next;
  for (const Slot& s : outbox_) {
    if (s.used && (!next || s.due < *next)) next = s.due;
  }
  return next;
}

}  // namespace ecat::slave::faults
