// Internal constants of the drive's implementation files (not API).
#pragma once

#include <cstdint>

namespace ecat::ds402::detail {

inline constexpr std::uint32_t kFollowingErrorOff = 0xFFFFFFFF;  // 6065h all ones: no monitoring
inline constexpr double kMsPerS = 1000.0;
inline constexpr double kMaPerA = 1000.0;
inline constexpr double kTorqueWindowPerMille = 10.0;  // torque "target reached" band (no object in CiA 402)
inline constexpr double kMovingRpm = 0.1;              // slower counts as standing still
// 60FDh bits (CiA 402-2 §8.4.12): 0 negative limit, 1 positive limit, 2 home
// switch; the probe inputs in the manufacturer part.
inline constexpr std::uint32_t kDiNegativeLimit = 1u << 0;
inline constexpr std::uint32_t kDiPositiveLimit = 1u << 1;
inline constexpr std::uint32_t kDiHomeSwitch = 1u << 2;
inline constexpr std::uint32_t kDiProbe1 = 1u << 16;
inline constexpr std::uint32_t kDiProbe2 = 1u << 17;

}  // namespace ecat::ds402::detail
