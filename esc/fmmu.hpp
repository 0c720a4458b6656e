// Fieldbus Memory Management Unit: maps a bit-granular range of the 4 GiB
// logical address space onto physical ESC memory (ESC datasheet Section I
// §6, Section II 0x0600-0x06FF; ETG.1000.4 §6.6; shared/spec/esc-registers.md §6).
#pragma once

#include <cstdint>

namespace ecat::esc {

// Offsets inside one FMMU's 16-byte register block.
namespace fmmu_reg {
inline constexpr unsigned kLogicalStart = 0x0;  // 4 bytes
inline constexpr unsigned kLength = 0x4;        // 2 bytes
inline constexpr unsigned kLogicalStartBit = 0x6;
inline constexpr unsigned kLogicalStopBit = 0x7;
inline constexpr unsigned kPhysicalStart = 0x8;  // 2 bytes
inline constexpr unsigned kPhysicalStartBit = 0xA;
inline constexpr unsigned kType = 0xB;
inline constexpr unsigned kActivate = 0xC;
inline constexpr std::uint8_t kTypeRead = 0x01;
inline constexpr std::uint8_t kTypeWrite = 0x02;
inline constexpr std::uint8_t kActivateEnable = 0x01;
inline constexpr std::uint8_t kBitMask = 0x07;
}  // namespace fmmu_reg

// One FMMU's configuration, decoded from its register block.
struct Fmmu {
  std::uint32_t logical_start = 0;
  std::uint16_t length = 0;
  std::uint8_t logical_start_bit = 0;
  std::uint8_t logical_stop_bit = 0;
  std::uint16_t physical_start = 0;
  std::uint8_t physical_start_bit = 0;
  bool read = false;
  bool write = false;
  bool enabled = false;

  static Fmmu decode(const std::uint8_t* block) noexcept;

  // Usable: enabled, non-empty and the bit range well-formed.
  bool active() const noexcept {
    if (!enabled || length == 0 || (!read && !write)) return false;
    // A one-byte mapping needs stop bit >= start bit.
    return !(length == 1 && logical_stop_bit < logical_start_bit);
  }
  // First and last logical bit mapped (absolute bit numbers, 64-bit to avoid
  // overflow at the top of the 4 GiB space).
  std::uint64_t first_bit() const noexcept { return static_cast<std::uint64_t>(logical_start) * 8 + logical_start_bit; }
  std::uint64_t last_bit() const noexcept {
    return (static_cast<std::uint64_t>(logical_start) + length - 1) * 8 + logical_stop_bit;
  }
  // True when the mapping is whole bytes on both sides.
  bool byte_aligned() const noexcept;
};

}  // namespace ecat::esc
