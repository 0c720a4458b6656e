// Bit-granular copy between a packed image (process data, complete access)
// and an entry's little-endian value bytes. LSB first, as ETG.1000.6 §5.6.7.4.7
// (PDO mapping) and the ESC's bit-wise FMMU layout (ETG.1000.4 §6.6) place them.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ecat::coe {

// Copies `bits` bits from `src` (starting at bit 0) into `dst` at bit `dst_bit`.
// Bits of dst outside the range are kept.
inline void put_bits(std::uint8_t* dst, std::size_t dst_bit, const std::uint8_t* src, std::size_t bits) noexcept {
  if (dst_bit % 8 == 0 && bits % 8 == 0) {
    for (std::size_t i = 0; i < bits / 8; ++i) dst[dst_bit / 8 + i] = src[i];
    return;
  }
  for (std::size_t i = 0; i < bits; ++i) {
    const std::size_t d = dst_bit + i;
    const auto mask = static_cast<std::uint8_t>(1u << (d % 8));
    if ((src[i / 8] >> (i % 8)) & 1u) {
      dst[d / 8] = static_cast<std::uint8_t>(dst[d / 8] | mask);
    } else {
      dst[d / 8] = static_cast<std::uint8_t>(dst[d / 8] & ~mask);
    }
  }
}

// Copies `bits` bits from `src` at bit `src_bit` into `dst` starting at bit 0.
// The remaining high bits of the last dst byte are cleared.
inline void get_bits(std::uint8_t* dst, const std::uint8_t* src, std::size_t src_bit, std::size_t bits) noexcept {
  if (src_bit % 8 == 0 && bits % 8 == 0) {
    for (std::size_t i = 0; i < bits / 8; ++i) dst[i] = src[src_bit / 8 + i];
    return;
  }
  for (std::size_t i = 0; i < (bits + 7) / 8; ++i) dst[i] = 0;
  for (std::size_t i = 0; i < bits; ++i) {
    const std::size_t s = src_bit + i;
    if ((src[s / 8] >> (s % 8)) & 1u) dst[i / 8] = static_cast<std::uint8_t>(dst[i / 8] | (1u << (i % 8)));
  }
}

}  // namespace ecat::coe
