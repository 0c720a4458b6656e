// Helpers for the DC unit tests: little-endian register access on a DcUnit.
#pragma once

#include <array>
#include <cstdint>

#include "common/le.hpp"
#include "esc/dc/dc_registers.hpp"
#include "esc/dc/dc_unit.hpp"

namespace ecat::esc::test {

inline std::uint64_t dc_read(DcUnit& dc, std::uint16_t offset, std::size_t size, Nanoseconds t,
                             Side side = Side::Ecat) {
  std::array<std::uint8_t, 8> b{};
  dc.read(offset, std::span<std::uint8_t>(b.data(), size), t, side);
  return load_le<std::uint64_t>(b.data());
}

inline void dc_write(DcUnit& dc, std::uint16_t offset, std::uint64_t value, std::size_t size, Nanoseconds t,
                     Side side = Side::Ecat) {
  std::array<std::uint8_t, 8> b{};
  store_le(b.data(), value);
  dc.write(offset, std::span<const std::uint8_t>(b.data(), size), t, side);
}

inline constexpr Nanoseconds us(std::int64_t v) { return Nanoseconds{v * 1000}; }
inline constexpr Nanoseconds ms(std::int64_t v) { return Nanoseconds{v * 1000000}; }

}  // namespace ecat::esc::test
