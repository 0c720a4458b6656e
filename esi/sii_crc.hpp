// CRC-8 of the SII configuration area (ETG.1000.6 §5.4; sii-eeprom.md §2):
// polynomial x^8 + x^2 + x + 1 (0x07), initial value 0xFF, MSB first, no
// reflection, no final XOR, over bytes 0..13; stored in the low byte of word 7.
#pragma once

#include <cstdint>
#include <span>

namespace ecat::esi::sii {

inline constexpr std::uint8_t kCrcPolynomial = 0x07;
inline constexpr std::uint8_t kCrcInitial = 0xFF;

constexpr std::uint8_t crc8(std::span<const std::uint8_t> bytes) noexcept {
  std::uint8_t crc = kCrcInitial;
  for (std::uint8_t b : bytes) {
    crc = static_cast<std::uint8_t>(crc ^ b);
    for (int bit = 0; bit < 8; ++bit) {
      crc = (crc & 0x80u) ? static_cast<std::uint8_t>((crc << 1) ^ kCrcPolynomial)
                          : static_cast<std::uint8_t>(crc << 1);
    }
  }
  return crc;
}

}  // namespace ecat::esi::sii
