// Statusword 6041h (CiA 402-2 §8.4.2 / IEC 61800-7-201 §6.3.2): bits 0-3, 5
// and 6 encode the PDS state (Table 32); 4 voltage enabled, 7 warning, 9
// remote, 10 target reached, 11 internal limit active, 12/13 operation-mode
// specific, 14/15 manufacturer specific.
#pragma once

#include <cstdint>

namespace ecat::ds402::sw {

inline constexpr std::uint16_t kReadyToSwitchOn = 1u << 0;
inline constexpr std::uint16_t kSwitchedOn = 1u << 1;
inline constexpr std::uint16_t kOperationEnabled = 1u << 2;
inline constexpr std::uint16_t kFault = 1u << 3;
inline constexpr std::uint16_t kVoltageEnabled = 1u << 4;
inline constexpr std::uint16_t kQuickStop = 1u << 5;  // 0 = quick stop active
inline constexpr std::uint16_t kSwitchOnDisabled = 1u << 6;
inline constexpr std::uint16_t kWarning = 1u << 7;
inline constexpr std::uint16_t kRemote = 1u << 9;
inline constexpr std::uint16_t kTargetReached = 1u << 10;
inline constexpr std::uint16_t kInternalLimitActive = 1u << 11;
inline constexpr std::uint16_t kOpMode12 = 1u << 12;
inline constexpr std::uint16_t kOpMode13 = 1u << 13;

// Mode-specific names (CiA 402-2 per-mode chapters).
inline constexpr std::uint16_t kSetPointAcknowledge = kOpMode12;  // pp
inline constexpr std::uint16_t kFollowingError = kOpMode13;       // pp, csp
inline constexpr std::uint16_t kSpeedZero = kOpMode12;            // pv: speed = 0
inline constexpr std::uint16_t kMaxSlippage = kOpMode13;          // pv
inline constexpr std::uint16_t kHomingAttained = kOpMode12;       // hm
inline constexpr std::uint16_t kHomingError = kOpMode13;          // hm
inline constexpr std::uint16_t kIpModeActive = kOpMode12;         // ip
inline constexpr std::uint16_t kFollowsCommand = kOpMode12;       // csp/csv/cst

// Bits that carry the state, and the value per state (Table 32).
inline constexpr std::uint16_t kStateMask = 0x006F;
inline constexpr std::uint16_t kStateMaskNoQs = 0x004F;  // states where bit 5 is "x"
inline constexpr std::uint16_t kNotReadyToSwitchOn = 0x0000;
inline constexpr std::uint16_t kSwitchOnDisabledState = 0x0040;
inline constexpr std::uint16_t kReadyToSwitchOnState = 0x0021;
inline constexpr std::uint16_t kSwitchedOnState = 0x0023;
inline constexpr std::uint16_t kOperationEnabledState = 0x0027;
inline constexpr std::uint16_t kQuickStopActiveState = 0x0007;
inline constexpr std::uint16_t kFaultReactionActiveState = 0x000F;
inline constexpr std::uint16_t kFaultState = 0x0008;

}  // namespace ecat::ds402::sw
