// Synchronisation objects 1C32h (outputs, SM2) and 1C33h (inputs, SM3)
// (ETG.1000.6 §5.6.7.4.3, ETG.1020 "synchronisation"; coe-mailbox.md §11.3).
#pragma once

#include <cstdint>

namespace ecat::coe {

inline constexpr std::uint16_t kSmOutputParameter = 0x1C32;
inline constexpr std::uint16_t kSmInputParameter = 0x1C33;
inline constexpr std::uint16_t kErrorSettings = 0x10F1;
inline constexpr std::uint8_t kErrorSettingsSyncErrorLimit = 2;  // 10F1h:02

// 1C32h:01 / 1C33h:01 values.
enum class SyncMode : std::uint16_t {
  FreeRun = 0x00,
  SmSynchronous = 0x01,       // 1C32: SM2 event; 1C33: SM3 event (no outputs)
  DcSync0 = 0x02,
  DcSync1 = 0x03,
  SmSynchronousSm2 = 0x22,    // 1C33 only: inputs with the SM2 event
};

bool is_dc(SyncMode m) noexcept;
// True for the values ETG.1000.6 defines for this object (0x22 only in 1C33h).
bool is_defined_sync_mode(std::uint16_t value, bool inputs) noexcept;

// Subindices of 1C32h/1C33h.
namespace syncsub {
inline constexpr std::uint8_t kSyncMode = 0x01;
inline constexpr std::uint8_t kCycleTime = 0x02;
inline constexpr std::uint8_t kShiftTime = 0x03;
inline constexpr std::uint8_t kSyncModesSupported = 0x04;
inline constexpr std::uint8_t kMinimumCycleTime = 0x05;
inline constexpr std::uint8_t kCalcAndCopyTime = 0x06;
inline constexpr std::uint8_t kMinimumDelayTime = 0x07;
inline constexpr std::uint8_t kGetCycleTime = 0x08;
inline constexpr std::uint8_t kDelayTime = 0x09;
inline constexpr std::uint8_t kSmEventMissed = 0x0B;
inline constexpr std::uint8_t kCycleTimeTooSmall = 0x0C;
inline constexpr std::uint8_t kShiftTimeTooShort = 0x0D;
inline constexpr std::uint8_t kSyncError = 0x20;
}  // namespace syncsub

// 1C3xh:08 commands (ETG.1020): 0 stop, 1 start measuring, 2 reset counters.
inline constexpr std::uint16_t kGetCycleTimeReset = 2;

// 1C3xh:04 bits (coe-mailbox.md §11.3).
inline constexpr std::uint16_t kSupportsFreeRun = 1u << 0;
inline constexpr std::uint16_t kSupportsSmSynchronous = 1u << 1;
inline constexpr std::uint16_t kSupportsDc = 1u << 2;  // bits 3:2 = 01
inline constexpr std::uint16_t kSupportsSync1Shift = 1u << 5;  // bits 5:4 = 10

}  // namespace ecat::coe
