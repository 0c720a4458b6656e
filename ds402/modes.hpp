// Modes of operation 6060h/6061h and the supported drive modes 6502h
// (CiA 402-2 §8.4.8-§8.4.10).
#pragma once

#include <cstdint>

namespace ecat::ds402 {

enum class OperationMode : std::int8_t {
  None = 0,
  ProfilePosition = 1,
  Velocity = 2,  // vl (ds402/velocity_mode.hpp)
  ProfileVelocity = 3,
  ProfileTorque = 4,
  Homing = 6,
  InterpolatedPosition = 7,
  CyclicSyncPosition = 8,
  CyclicSyncVelocity = 9,
  CyclicSyncTorque = 10,
};

// 6502h bits.
namespace supported {
inline constexpr std::uint32_t kPp = 1u << 0;
inline constexpr std::uint32_t kVl = 1u << 1;
inline constexpr std::uint32_t kPv = 1u << 2;
inline constexpr std::uint32_t kTq = 1u << 3;
inline constexpr std::uint32_t kHm = 1u << 5;
inline constexpr std::uint32_t kIp = 1u << 6;
inline constexpr std::uint32_t kCsp = 1u << 7;
inline constexpr std::uint32_t kCsv = 1u << 8;
inline constexpr std::uint32_t kCst = 1u << 9;
}  // namespace supported

// The 6502h bit of a mode (0 for "no mode" and for manufacturer modes).
constexpr std::uint32_t supported_bit(std::int8_t mode) noexcept {
  switch (mode) {
    case 1: return supported::kPp;
    case 2: return supported::kVl;
    case 3: return supported::kPv;
    case 4: return supported::kTq;
    case 6: return supported::kHm;
    case 7: return supported::kIp;
    case 8: return supported::kCsp;
    case 9: return supported::kCsv;
    case 10: return supported::kCst;
    default: return 0;
  }
}

// Modes the generic drive advertises (vl is simulated too, but only the
// personalities whose manual lists it advertise it).
inline constexpr std::uint32_t kSimulatedModes = supported::kPp | supported::kPv | supported::kTq |
                                                supported::kHm | supported::kIp | supported::kCsp |
                                                supported::kCsv | supported::kCst;

constexpr bool is_position_mode(OperationMode m) noexcept {
  return m == OperationMode::ProfilePosition || m == OperationMode::Homing ||
         m == OperationMode::CyclicSyncPosition || m == OperationMode::InterpolatedPosition;
}

}  // namespace ecat::ds402
