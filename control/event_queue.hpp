// The control interface's events (docs/control.md "Events"): AL state
// changes, AL control requests, SDO writes, emergencies sent, faults engaged
// and cleared, link changes. Each gets a sequence number; the newest
// `capacity` are kept, so a client that polls with {"cmd":"events","since":N}
// or a stream that fell behind learns how many it missed. Only the control
// side pushes (event_watcher.cpp on a slow tick, the fault observer): nothing
// here runs per frame.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>

#include <nlohmann/json.hpp>

namespace ecat::control {

class EventQueue {
 public:
  static constexpr std::size_t kDefaultCapacity = 4096;
  explicit EventQueue(std::size_t capacity = kDefaultCapacity) : capacity_(capacity == 0 ? 1 : capacity) {}

  // Adds "seq" to `event` and keeps it (the oldest goes when full).
  void push(nlohmann::json event);
  // The sequence number the next event will get.
  std::uint64_t next_seq() const noexcept { return next_; }
  // The oldest sequence number still kept (next_seq() when empty).
  std::uint64_t first_seq() const noexcept { return next_ - events_.size(); }
  // {"events": [events with seq >= since, at most max], "next": seq to ask
  // for next time, "lost": events older than the kept ones that were asked for}.
  nlohmann::json since(std::uint64_t since, std::size_t max) const;

 private:
  std::size_t capacity_;
  std::deque<nlohmann::json> events_;
  std::uint64_t next_ = 0;
};

}  // namespace ecat::control
