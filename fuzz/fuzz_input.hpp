// Splits a fuzzer input into records, so one input can carry a sequence of
// frames or mailbox operations: [u16 little-endian length][bytes]... A
// truncated last record takes what is left. Bounds-checked through le.hpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "common/le.hpp"

namespace ecat::fuzz {

class Records {
 public:
  Records(const std::uint8_t* data, std::size_t size) noexcept : rest_(data, size) {}

  // The next record, or nullopt-like empty span with ok=false at the end.
  bool next(std::span<const std::uint8_t>& out, std::size_t max_length) noexcept {
    constexpr std::size_t kLengthBytes = 2;
    if (rest_.size() < kLengthBytes) return false;
    std::size_t n = load_le<std::uint16_t>(rest_.data());
    rest_ = rest_.subspan(kLengthBytes);
    n = std::min({n, rest_.size(), max_length});
    out = rest_.first(n);
    rest_ = rest_.subspan(n);
    return true;
  }

 private:
  std::span<const std::uint8_t> rest_;
};

}  // namespace ecat::fuzz
