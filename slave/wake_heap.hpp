// The slaves of a chain by the time they next need to run (issue 16 item 5):
// a binary min-heap over slave indices with each slave's position kept, so
// a slave's wake time is changed in place (O(log n)) and the ones due are
// taken from the top. Sized at set-up; nothing allocates afterwards.
#pragma once

#include <cstdint>
#include <vector>

#include "common/clock.hpp"

namespace ecat::slave {

class WakeHeap {
 public:
  // Set-up: slaves 0..n-1, the new ones waking at `at`.
  void resize(std::size_t n, Nanoseconds at = Nanoseconds::min()) {
    for (std::size_t i = key_.size(); i < n; ++i) {
      key_.push_back(at);
      pos_.push_back(static_cast<std::uint32_t>(heap_.size()));
      heap_.push_back(static_cast<std::uint32_t>(i));
      up(heap_.size() - 1);
    }
  }
  bool empty() const noexcept { return heap_.empty(); }
  // The slave that wakes first, and when.
  std::size_t top() const noexcept { return heap_.front(); }
  Nanoseconds top_time() const noexcept { return key_[heap_.front()]; }
  Nanoseconds time(std::size_t i) const noexcept { return key_[i]; }

  void set(std::size_t i, Nanoseconds at) noexcept {
    const Nanoseconds was = key_[i];
    key_[i] = at;
    if (at < was) {
      up(pos_[i]);
    } else if (was < at) {
      down(pos_[i]);
    }
  }

 private:
  void place(std::size_t at, std::uint32_t slave) noexcept {
    heap_[at] = slave;
    pos_[slave] = static_cast<std::uint32_t>(at);
  }
  void up(std::size_t at) noexcept {
    const std::uint32_t s = heap_[at];
    while (at > 0) {
      const std::size_t parent = (at - 1) / 2;
      if (!(key_[s] < key_[heap_[parent]])) break;
      place(at, heap_[parent]);
      at = parent;
    }
    place(at, s);
  }
  void down(std::size_t at) noexcept {
    const std::uint32_t s = heap_[at];
    const std::size_t n = heap_.size();
    for (;;) {
      std::size_t child = 2 * at + 1;
      if (child >= n) break;
      if (child + 1 < n && key_[heap_[child + 1]] < key_[heap_[child]]) ++child;
      if (!(key_[heap_[child]] < key_[s])) break;
      place(at, heap_[child]);
      at = child;
    }
    place(at, s);
  }

  std::vector<Nanoseconds> key_;     // per slave: when it wakes
  std::vector<std::uint32_t> pos_;   // per slave: its place in heap_
  std::vector<std::uint32_t> heap_;  // slave indices, earliest first
};

}  // namespace ecat::slave
