// PDO mapping and assignment words (CiA 301 §7.5.2.36, ETG.1000.6 §5.6.7.4.7-9;
// shared/spec/coe-mailbox.md §11.1-11.2): a mapping entry is
// (index << 16) | (subindex << 8) | bit length; index 0 (or a CiA 301 dummy
// data-type index 1..7) with subindex 0 is a gap of that many bits.
#pragma once

#include <cstdint>

namespace ecat::coe {

enum class PdoDirection : std::uint8_t { Rx, Tx };  // Rx = outputs (SM2), Tx = inputs (SM3)

inline constexpr std::uint16_t kRxPdoMappingFirst = 0x1600;
inline constexpr std::uint16_t kRxPdoMappingLast = 0x17FF;
inline constexpr std::uint16_t kTxPdoMappingFirst = 0x1A00;
inline constexpr std::uint16_t kTxPdoMappingLast = 0x1BFF;
inline constexpr std::uint16_t kSmCommunicationType = 0x1C00;
inline constexpr std::uint16_t kSmPdoAssignBase = 0x1C10;  // + SM number
inline constexpr std::uint16_t kSmPdoAssignCount = 32;      // 1C10h-1C2Fh: SM 0-31
inline constexpr std::uint16_t kRxPdoAssign = 0x1C12;      // SM2
inline constexpr std::uint16_t kTxPdoAssign = 0x1C13;      // SM3
inline constexpr unsigned kOutputsSm = 2;
inline constexpr unsigned kInputsSm = 3;
inline constexpr std::uint16_t kLastDummyIndex = 0x0007;  // CiA 301 §7.4.7.1 dummy mapping

struct PdoMappingEntry {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  std::uint8_t bit_length = 0;

  static constexpr PdoMappingEntry decode(std::uint32_t v) noexcept {
    return {static_cast<std::uint16_t>(v >> 16), static_cast<std::uint8_t>(v >> 8), static_cast<std::uint8_t>(v)};
  }
  constexpr std::uint32_t encode() const noexcept {
    return (std::uint32_t{index} << 16) | (std::uint32_t{subindex} << 8) | bit_length;
  }
  constexpr bool is_gap() const noexcept { return index <= kLastDummyIndex && subindex == 0; }
};

constexpr bool is_mapping_index(std::uint16_t index, PdoDirection d) noexcept {
  return d == PdoDirection::Rx ? (index >= kRxPdoMappingFirst && index <= kRxPdoMappingLast)
                               : (index >= kTxPdoMappingFirst && index <= kTxPdoMappingLast);
}
constexpr bool is_mapping_index(std::uint16_t index) noexcept {
  return is_mapping_index(index, PdoDirection::Rx) || is_mapping_index(index, PdoDirection::Tx);
}
constexpr std::uint16_t assign_index(PdoDirection d) noexcept {
  return d == PdoDirection::Rx ? kRxPdoAssign : kTxPdoAssign;
}

}  // namespace ecat::coe
