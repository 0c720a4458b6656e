// Controlword 6040h (CiA 402-2 §8.4.1 / IEC 61800-7-201 §6.3.1): the device
// control commands are decoded from bits 0-3 and 7; bits 4-6, 8 and 9 are
// operation-mode specific (§8.4.1 Table 31, per-mode chapters).
#pragma once

#include <cstdint>

namespace ecat::ds402 {

namespace cw {
inline constexpr std::uint16_t kSwitchOn = 1u << 0;
inline constexpr std::uint16_t kEnableVoltage = 1u << 1;
inline constexpr std::uint16_t kQuickStop = 1u << 2;  // 0 = quick stop requested
inline constexpr std::uint16_t kEnableOperation = 1u << 3;
inline constexpr std::uint16_t kOpMode4 = 1u << 4;  // pp: new set-point, hm: start, ip: enable
inline constexpr std::uint16_t kOpMode5 = 1u << 5;  // pp: change set immediately
inline constexpr std::uint16_t kOpMode6 = 1u << 6;  // pp: 0 absolute / 1 relative
inline constexpr std::uint16_t kFaultReset = 1u << 7;
inline constexpr std::uint16_t kHalt = 1u << 8;
inline constexpr std::uint16_t kOpMode9 = 1u << 9;  // pp: change on set-point

// Named aliases of the mode-specific bits.
inline constexpr std::uint16_t kNewSetPoint = kOpMode4;
inline constexpr std::uint16_t kHomingStart = kOpMode4;
inline constexpr std::uint16_t kEnableIpMode = kOpMode4;
inline constexpr std::uint16_t kChangeSetImmediately = kOpMode5;
inline constexpr std::uint16_t kRelative = kOpMode6;
inline constexpr std::uint16_t kChangeOnSetPoint = kOpMode9;

// Commands as CiA 402-2 Table 30 writes them: value under mask.
inline constexpr std::uint16_t kShutdownMask = 0x0087, kShutdownValue = 0x0006;
inline constexpr std::uint16_t kSwitchOnMask = 0x008F, kSwitchOnValue = 0x0007;
inline constexpr std::uint16_t kEnableOperationMask = 0x008F, kEnableOperationValue = 0x000F;
inline constexpr std::uint16_t kDisableVoltageMask = 0x0082, kDisableVoltageValue = 0x0000;
inline constexpr std::uint16_t kQuickStopMask = 0x0086, kQuickStopValue = 0x0002;
}  // namespace cw

// Device control commands (Table 30). "Disable operation" has the same bit
// pattern as "switch on"; the state decides which transition it causes.
enum class Command : std::uint8_t {
  None,  // bit 7 set (fault reset pending) or a pattern the table does not name
  Shutdown,
  SwitchOn,  // also "disable operation" in Operation enabled
  EnableOperation,  // also "switch on + enable operation" from Ready to switch on
  DisableVoltage,
  QuickStop,
};

constexpr Command decode_command(std::uint16_t controlword) noexcept {
  if (controlword & cw::kFaultReset) return Command::None;
  if ((controlword & cw::kDisableVoltageMask) == cw::kDisableVoltageValue) return Command::DisableVoltage;
  if ((controlword & cw::kQuickStopMask) == cw::kQuickStopValue) return Command::QuickStop;
  if ((controlword & cw::kShutdownMask) == cw::kShutdownValue) return Command::Shutdown;
  if ((controlword & cw::kEnableOperationMask) == cw::kEnableOperationValue) return Command::EnableOperation;
  if ((controlword & cw::kSwitchOnMask) == cw::kSwitchOnValue) return Command::SwitchOn;
  return Command::None;
}

}  // namespace ecat::ds402
