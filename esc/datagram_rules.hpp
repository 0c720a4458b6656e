// Rules every datagram handler of the ESC shares (esc/datagram_engine.cpp,
// esc/logical_access.cpp): the working-counter increments of ETG.1000.4
// §5.4.3 (read +1, write +1, the write part of a read-write command +2)
// and the scratch buffer for one datagram's data.
#pragma once

#include <array>
#include <cstdint>

#include "common/frame.hpp"

namespace ecat::esc {

inline constexpr std::uint16_t kWkcRead = 1;
inline constexpr std::uint16_t kWkcWrite = 1;
inline constexpr std::uint16_t kWkcReadWriteWrite = 2;  // the write part of an xRW / LRW

// Scratch for one datagram's data (11-bit length), on the stack: no heap.
using DatagramScratch = std::array<std::uint8_t, kFrameLengthMask + 1>;

}  // namespace ecat::esc
