// Classification of the register bytes 0x0000-0x0FFF for the fast path of
// register accesses (issue 8): which bytes a plain copy may read or write
// for a side, and which need the per-byte handlers of
// esc/register_access.cpp (Beckhoff ESC datasheet Section II: events,
// acknowledging reads, masked writes, writes with side effects).
//
// Built at compile time from fixed_register_write_mask() and the lists of
// bytes with side effects below; the lists must name every byte whose
// handling in reg_read_byte / reg_write_byte / after_register_write is more
// than "return the stored byte" / "store the byte". tests/esc/
// esc_register_map_test.cpp checks every byte of both sides against the
// behaviour of the slow path.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "esc/access_side.hpp"
#include "esc/register_masks.hpp"
#include "esc/registers.hpp"
#include "esc/sii_interface.hpp"

namespace ecat::esc::register_map {

inline constexpr std::size_t kRegisterBytes = reg::kProcessRam;
inline constexpr unsigned kBlockShift = 4;  // 16-byte blocks for the range checks
inline constexpr std::size_t kBlocks = kRegisterBytes >> kBlockShift;

// Per-byte flags.
inline constexpr std::uint8_t kReadEffectEcat = 0x01;  // computed or acknowledging on an ECAT read
inline constexpr std::uint8_t kReadEffectPdi = 0x02;
inline constexpr std::uint8_t kWritePlainEcat = 0x04;  // all 8 bits writable, nothing else happens
inline constexpr std::uint8_t kWritePlainPdi = 0x08;

constexpr std::uint8_t read_effect_flag(Side side) noexcept {
  return side == Side::Ecat ? kReadEffectEcat : kReadEffectPdi;
}
constexpr std::uint8_t write_plain_flag(Side side) noexcept {
  return side == Side::Ecat ? kWritePlainEcat : kWritePlainPdi;
}

// The watchdog divider 0x0400 and times 0x0410/0x0420 (16 bit each), whose
// timeouts Esc keeps (Watchdogs::set_times).
constexpr bool watchdog_setting(std::uint16_t a) noexcept {
  constexpr std::uint16_t kBytes = 2;
  const auto at = [a](std::uint16_t first) { return a >= first && a < first + kBytes; };
  return at(reg::kWatchdogDivider) || at(reg::kWatchdogTimePdi) || at(reg::kWatchdogTimeProcessData);
}

namespace detail {

constexpr bool in(std::uint16_t a, std::uint16_t first, std::uint16_t end) noexcept { return a >= first && a < end; }

// Blocks with their own handlers on every access.
constexpr bool special_block(std::uint16_t a) noexcept {
  return in(a, reg::kDcBase, reg::kDcEnd) ||
         in(a, reg::kEepromConfiguration, static_cast<std::uint16_t>(reg::kEepromConfiguration + sii_reg::kSize)) ||
         in(a, reg::kFmmuBase, reg_layout::kFmmuEnd) || in(a, reg::kSyncManagerBase, reg_layout::kSmEnd);
}

// Reads that are computed (event requests) or acknowledge something
// (Section II 0x0110, 0x0120, 0x0130, 0x0210, 0x0220, 0x0440, 0x0805, 0x0806).
constexpr bool read_effect(std::uint16_t a, Side side) noexcept {
  if (in(a, reg::kEcatEventRequest, reg::kEcatEventRequest + 2)) return true;
  if (in(a, reg::kAlEventRequest, reg::kAlEventRequest + 4)) return true;
  if (in(a, reg::kDcBase, reg::kDcEnd) || in(a, reg::kSyncManagerBase, reg_layout::kSmEnd)) return true;
  if (side == Side::Ecat) return a == reg::kAlStatus || a == reg::kDlStatus;
  return a == reg::kAlControl || a == reg::kAlControl + 1 || a == reg::kWatchdogStatusProcessData;
}

// Writes that do more than store the value (write enables, reset sequence,
// DL control, AL control/status, counters cleared by any write, MII command,
// the watchdog divider and times, whose timeouts Watchdogs keeps;
// the station address, alias and ECAT event mask advance the ESC's address
// epoch, Esc::address_epoch_).
constexpr bool write_effect(std::uint16_t a, Side side) noexcept {
  if (special_block(a)) return true;
  if (a == reg::kEscResetEcat || a == reg::kEscResetPdi) return true;
  if (in(a, reg::kDlControl, reg::kDlControl + 4)) return true;
  if (in(a, reg::kConfiguredStationAddress, reg::kConfiguredStationAlias + 2)) return true;
  if (in(a, reg::kEcatEventMask, reg::kEcatEventMask + 2)) return true;
  if (side == Side::Pdi) return a == reg::kAlStatus;
  return a == reg::kRegisterWriteEnable || a == reg::kEscWriteEnable || a == reg::kAlControl ||
         a == reg::kAlControl + 1 || in(a, reg::kRxErrorCounter, bits::kLostLinkCountersEnd) ||
         a == reg::kWatchdogCounterProcessData || a == reg::kWatchdogCounterPdi ||
         watchdog_setting(a) ||
         in(a, reg_layout::kMiiControl, reg_layout::kMiiPhyAddress);
}

constexpr std::uint8_t classify(std::uint16_t a) noexcept {
  constexpr std::uint8_t kAll = 0xFF;
  const RegisterWriteMask m = fixed_register_write_mask(a);
  std::uint8_t f = 0;
  if (read_effect(a, Side::Ecat)) f |= kReadEffectEcat;
  if (read_effect(a, Side::Pdi)) f |= kReadEffectPdi;
  if (m.ecat == kAll && !write_effect(a, Side::Ecat)) f |= kWritePlainEcat;
  if (m.pdi == kAll && !write_effect(a, Side::Pdi)) f |= kWritePlainPdi;
  return f;
}

struct Table {
  std::array<std::uint8_t, kRegisterBytes> byte{};
  std::array<std::uint8_t, kBlocks> block_any{};  // OR of the block's byte flags
  std::array<std::uint8_t, kBlocks> block_all{};  // AND of the block's byte flags
};

constexpr Table build() noexcept {
  Table t;
  constexpr std::size_t kBlockBytes = std::size_t{1} << kBlockShift;
  for (std::size_t b = 0; b < kBlocks; ++b) {
    std::uint8_t any = 0;
    auto all = static_cast<std::uint8_t>(0xFF);
    for (std::size_t i = 0; i < kBlockBytes; ++i) {
      const auto a = static_cast<std::uint16_t>(b * kBlockBytes + i);
      t.byte[a] = classify(a);
      any = static_cast<std::uint8_t>(any | t.byte[a]);
      all = static_cast<std::uint8_t>(all & t.byte[a]);
    }
    t.block_any[b] = any;
    t.block_all[b] = all;
  }
  return t;
}

}  // namespace detail

inline constexpr detail::Table kTable = detail::build();

// Flag of one register byte (address < 0x1000).
inline bool has(std::uint16_t address, std::uint8_t flag) noexcept { return (kTable.byte[address] & flag) != 0; }

// Whether some byte of the blocks touched by [address, address + n) may have
// `flag` (conservative: per 16-byte block). n > 0, address + n <= 0x1000.
inline bool any_in(std::uint16_t address, std::size_t n, std::uint8_t flag) noexcept {
  const std::size_t last = (address + n - 1) >> kBlockShift;
  for (std::size_t b = address >> kBlockShift; b <= last; ++b) {
    if (kTable.block_any[b] & flag) return true;
  }
  return false;
}

// Whether every byte of the blocks touched by [address, address + n) has `flag`.
inline bool all_in(std::uint16_t address, std::size_t n, std::uint8_t flag) noexcept {
  const std::size_t last = (address + n - 1) >> kBlockShift;
  for (std::size_t b = address >> kBlockShift; b <= last; ++b) {
    if (!(kTable.block_all[b] & flag)) return false;
  }
  return true;
}

}  // namespace ecat::esc::register_map
