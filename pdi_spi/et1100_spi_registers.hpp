// Beckhoff ET1100/ET1200 SPI slave PDI framing (ESC datasheet Section III
// "SPI slave interface"; docs/real-esc.md cites each item). Every access is
// an address/command phase followed by a data phase, inside one chip-select
// assertion; MSB first on the wire, data bytes in ascending ESC address.
#pragma once

#include <cstdint>

namespace ecat::pdi_spi::et1100 {

// Command bits CMD[2:0] of the address phase.
inline constexpr std::uint8_t kCmdNop = 0x0;
inline constexpr std::uint8_t kCmdRead = 0x2;
inline constexpr std::uint8_t kCmdReadWaitState = 0x3;
inline constexpr std::uint8_t kCmdWrite = 0x4;
inline constexpr std::uint8_t kCmdAddressExtension = 0x6;  // 3-byte addressing

// 2-byte address phase: byte 0 = A[12:5], byte 1 = A[4:0] << 3 | CMD.
// 3-byte: byte 1 carries the address-extension command, byte 2 =
// A[15:13] << 5 | CMD << 2 (bits 1:0 reserved, 0).
inline constexpr unsigned kAddressHighShift = 5;
inline constexpr std::uint8_t kAddressLowMask = 0x1F;
inline constexpr unsigned kAddressLowShift = 3;
inline constexpr std::uint8_t kCommandMask = 0x07;
inline constexpr unsigned kExtensionAddressShift = 13;
inline constexpr unsigned kExtensionByteAddressShift = 5;
inline constexpr unsigned kExtensionCommandShift = 2;
inline constexpr std::uint16_t kTwoByteAddressLimit = 0x2000;  // 13 address bits

// During the address phase MISO carries the AL event request register:
// 0x0220, 0x0221 (and 0x0222 with 3-byte addressing).
inline constexpr std::uint16_t kAlEventRequest = 0x0220;

// MOSI during a read's data phase: 0x00 for every byte but the last, 0xFF
// for the last (read termination: the ESC stops prefetching). The wait
// state byte of command 3 is 0xFF.
inline constexpr std::uint8_t kReadNext = 0x00;
inline constexpr std::uint8_t kReadTermination = 0xFF;
inline constexpr std::uint8_t kWaitStateByte = 0xFF;

inline constexpr unsigned kBitsPerByte = 8;  // SPI clocks per byte

// PDI error code 0x030E of the SPI slave, "reasons for last PDI error"
// (ESC datasheet Section II §2.9.5.1 "SPI slave error code"; 0x030D counts
// each access with an interface error, §2.9.4). Bits 15:8 (0x030F) are
// for SEL_MISO/SEL_MOSI accesses, which these chips do not have: 0.
inline constexpr std::uint8_t kPdiErrorClockCountMask = 0x07;           // 2:0 SPI clocks of the access, modulo 8
inline constexpr std::uint8_t kPdiErrorReadBusyViolation = 1u << 3;      // not detected by the emulation (no timing)
inline constexpr std::uint8_t kPdiErrorReadTerminationMissing = 1u << 4;
inline constexpr std::uint8_t kPdiErrorAccessAfterTermination = 1u << 5;  // bytes clocked after the termination byte
inline constexpr unsigned kPdiErrorCommandShift = 6;                      // 7:6 CMD[2:1] of the access
inline constexpr std::uint8_t kPdiErrorCommandBits = 0x3;

}  // namespace ecat::pdi_spi::et1100
