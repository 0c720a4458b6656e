// The last N records of something that happens now and then (an SDO write,
// an emergency sent), with the count of all of them: a reader that kept the
// count it last saw finds what happened since without a callback into its
// layer (control/event_watcher.cpp samples these on a slow tick). Fixed
// size, no heap; a reader that falls more than N behind has lost the oldest
// (it can tell: count() - seen > N).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

namespace ecat::coe {

template <typename Record, std::size_t N>
class RecentLog {
 public:
  static constexpr std::size_t kCapacity = N;

  void add(const Record& r) noexcept {
    ring_[count_ % N] = r;
    ++count_;
  }
  // How many were ever added.
  std::uint64_t count() const noexcept { return count_; }
  // Record number n (0-based, n < count()), if still kept.
  std::optional<Record> at(std::uint64_t n) const noexcept {
    if (n >= count_ || count_ - n > N) return std::nullopt;
    return ring_[n % N];
  }

 private:
  std::array<Record, N> ring_{};
  std::uint64_t count_ = 0;
};

}  // namespace ecat::coe
