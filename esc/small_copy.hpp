// Register accesses are mostly 1, 2, 4 or 8 bytes: copy those as one move,
// inline, instead of through a library call (issue 8: ESC datagram path).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace ecat::esc {

inline void copy_small(std::uint8_t* dst, const std::uint8_t* src, std::size_t n) noexcept {
  switch (n) {
    case 1: dst[0] = src[0]; break;
    case 2: std::memcpy(dst, src, 2); break;
    case 4: std::memcpy(dst, src, 4); break;
    case 8: std::memcpy(dst, src, 8); break;
    default: std::memcpy(dst, src, n); break;
  }
}

}  // namespace ecat::esc
