// The 6-byte mailbox header and the mailbox error reply (ETG.1000.4 §5.6,
// ETG.1000.6 §5.6.1; shared/spec/coe-mailbox.md §1-2).
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "common/le.hpp"

namespace ecat::coe {

enum class MailboxType : std::uint8_t {
  Error = 0x0,
  AoE = 0x1,
  EoE = 0x2,
  CoE = 0x3,
  FoE = 0x4,
  SoE = 0x5,
  VoE = 0xF,
};

// Detail code of a mailbox error reply (ETG.1000.6 Table 29).
enum class MailboxError : std::uint16_t {
  Syntax = 0x0001,
  UnsupportedProtocol = 0x0002,
  InvalidChannel = 0x0003,
  ServiceNotSupported = 0x0004,
  InvalidHeader = 0x0005,
  SizeTooShort = 0x0006,
  NoMoreMemory = 0x0007,
  InvalidSize = 0x0008,
};

std::string_view describe(MailboxError error) noexcept;

struct MailboxHeader {
  static constexpr std::size_t kSize = 6;
  static constexpr std::uint8_t kChannelMask = 0x3F;
  static constexpr std::uint8_t kPriorityShift = 6;
  static constexpr std::uint8_t kTypeMask = 0x0F;
  static constexpr std::uint8_t kCounterShift = 4;
  static constexpr std::uint8_t kCounterMask = 0x07;
  static constexpr std::uint8_t kReservedBit = 0x80;
  static constexpr std::uint8_t kCounterMax = 7;

  std::uint16_t length = 0;   // payload bytes after the header
  std::uint16_t address = 0;  // originator station address; 0 = master
  std::uint8_t channel = 0;
  std::uint8_t priority = 0;
  std::uint8_t type = 0;      // MailboxType value (raw: unknown types are kept)
  std::uint8_t counter = 0;   // 0 = not used, else 1..7
  bool reserved = false;      // byte 5 bit 7

  static std::optional<MailboxHeader> unpack(ConstBytes in) noexcept;
  void pack(Bytes out) const noexcept;

  // Counter after `c` for the slave's own replies: 1..7, wrapping to 1.
  static constexpr std::uint8_t next_counter(std::uint8_t c) noexcept {
    return c >= kCounterMax ? 1 : static_cast<std::uint8_t>(c + 1);
  }
};

// Mailbox error reply payload: service 0x0001 ("error") then the detail code.
inline constexpr std::uint16_t kMailboxErrorService = 0x0001;
inline constexpr std::size_t kMailboxErrorPayload = 4;

}  // namespace ecat::coe
