// How late the master's cycles started (issue 19): each cycle's wake-up minus
// the time it was scheduled for, in fixed buckets, printed with the cycle
// statistics (`lateness-us <10:N <50:N ...`). The same edges as the probe
// tests/measure/wake_probe.c, so the two can be compared line by line.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include <fmt/format.h>

#include "common/clock.hpp"

namespace ecat::app {

class LatenessHistogram {
 public:
  static constexpr std::array<std::int64_t, 9> kEdgesUs{10, 50, 100, 250, 500, 1000, 2000, 5000, 20000};

  void add(Nanoseconds late) noexcept {
    std::size_t b = 0;
    while (b < kEdgesUs.size() && late.count() >= kEdgesUs[b] * kNsPerUs) ++b;
    ++counts_[b];
    if (late > max_) max_ = late;
  }
  std::uint64_t count(std::size_t bucket) const noexcept { return counts_.at(bucket); }
  Nanoseconds max() const noexcept { return max_; }
  // "<10:N <50:N ... >=20000:N" (microseconds).
  std::string to_string() const {
    std::string s;
    for (std::size_t b = 0; b < kEdgesUs.size(); ++b) s += fmt::format("<{}:{} ", kEdgesUs[b], counts_[b]);
    s += fmt::format(">={}:{}", kEdgesUs.back(), counts_.back());
    return s;
  }

 private:
  static constexpr std::int64_t kNsPerUs = 1000;
  std::array<std::uint64_t, kEdgesUs.size() + 1> counts_{};
  Nanoseconds max_{0};
};

}  // namespace ecat::app
