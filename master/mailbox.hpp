// Mailbox header (ETG.1000.4 §5.6 / ETG.1000.6 §5.6; coe-mailbox.md §1-§2).
#pragma once

#include <cstdint>

namespace ecat::master::mbx {

inline constexpr std::size_t kHeaderSize = 6;
inline constexpr std::uint8_t kTypeError = 0x0;
inline constexpr std::uint8_t kTypeAoe = 0x1;
inline constexpr std::uint8_t kTypeEoe = 0x2;
inline constexpr std::uint8_t kTypeCoe = 0x3;
inline constexpr std::uint8_t kTypeFoe = 0x4;
inline constexpr std::uint8_t kTypeSoe = 0x5;
inline constexpr std::uint8_t kTypeVoe = 0xF;
inline constexpr std::uint8_t kTypeMask = 0x0F;
inline constexpr unsigned kCounterShift = 4;
inline constexpr std::uint8_t kCounterMask = 0x07;
inline constexpr std::uint8_t kCounterMax = 7;
inline constexpr std::uint16_t kErrorServiceType = 0x0001;  // mailbox error reply "service"

// Mailbox error reply detail codes (coe-mailbox.md §2).
enum class MailboxErrorCode : std::uint16_t {
  None = 0,
  Syntax = 0x0001,
  UnsupportedProtocol = 0x0002,
  InvalidChannel = 0x0003,
  ServiceNotSupported = 0x0004,
  InvalidHeader = 0x0005,
  SizeTooShort = 0x0006,
  NoMoreMemory = 0x0007,
  InvalidSize = 0x0008,
  ServiceInWork = 0x0009,
};

// Next counter after `c`: 1..7, wrapping 7 -> 1, never 0 (SOEM ec_nextmbxcnt).
constexpr std::uint8_t next_counter(std::uint8_t c) noexcept {
  return c >= kCounterMax ? std::uint8_t{1} : static_cast<std::uint8_t>(c + 1);
}

struct Header {
  std::uint16_t length = 0;   // payload bytes after the header
  std::uint16_t address = 0;
  std::uint8_t channel_priority = 0;
  std::uint8_t type = 0;
  std::uint8_t counter = 0;
};

}  // namespace ecat::master::mbx
