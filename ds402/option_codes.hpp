// Option codes 605Ah-605Eh (CiA 402-2 §8.4.3-§8.4.7): how the drive stops on
// quick stop, shutdown, disable operation, halt and a fault.
#pragma once

#include <cstdint>

namespace ecat::ds402 {

// 605Ah quick stop option code.
enum class QuickStopOption : std::int16_t {
  DisableDrive = 0,          // coast, then Switch on disabled
  SlowDownRamp = 1,          // 6084h, then Switch on disabled
  QuickStopRamp = 2,         // 6085h, then Switch on disabled
  CurrentLimit = 3,          // at the torque limit, then Switch on disabled
  VoltageLimit = 4,          // at the voltage limit, then Switch on disabled
  SlowDownRampStay = 5,      // 6084h, stay in Quick stop active
  QuickStopRampStay = 6,     // 6085h, stay in Quick stop active
  CurrentLimitStay = 7,
  VoltageLimitStay = 8,
};

// 605Bh (shutdown) and 605Ch (disable operation) option codes.
enum class DisableOption : std::int16_t {
  DisableDrive = 0,  // power stage off at once, motor coasts
  SlowDownRamp = 1,  // 6084h, then power stage off
};

// 605Dh halt option code (the drive stays in Operation enabled).
enum class HaltOption : std::int16_t {
  SlowDownRamp = 1,
  QuickStopRamp = 2,
  CurrentLimit = 3,
  VoltageLimit = 4,
};

// 605Eh fault reaction option code.
enum class FaultReactionOption : std::int16_t {
  DisableDrive = 0,
  SlowDownRamp = 1,
  QuickStopRamp = 2,
  CurrentLimit = 3,
  VoltageLimit = 4,
};

// The stop the motion layer carries out.
enum class StopKind : std::uint8_t {
  None,
  Coast,          // power stage off
  SlowDownRamp,   // 6084h profile deceleration
  QuickStopRamp,  // 6085h quick stop deceleration
  TorqueLimit,    // current (or voltage) limit: decelerate at the torque limit
};

constexpr StopKind stop_for_quick_stop(std::int16_t code) noexcept {
  switch (code) {
    case 0: return StopKind::Coast;
    case 1: case 5: return StopKind::SlowDownRamp;
    case 2: case 6: return StopKind::QuickStopRamp;
    case 3: case 4: case 7: case 8: return StopKind::TorqueLimit;
    default: return StopKind::QuickStopRamp;
  }
}
constexpr bool quick_stop_stays(std::int16_t code) noexcept { return code >= 5 && code <= 8; }

constexpr StopKind stop_for_disable(std::int16_t code) noexcept {
  return code == 1 ? StopKind::SlowDownRamp : StopKind::Coast;
}

constexpr StopKind stop_for_halt(std::int16_t code) noexcept {
  switch (code) {
    case 2: return StopKind::QuickStopRamp;
    case 3: case 4: return StopKind::TorqueLimit;
    default: return StopKind::SlowDownRamp;
  }
}

constexpr StopKind stop_for_fault(std::int16_t code) noexcept {
  switch (code) {
    case 1: return StopKind::SlowDownRamp;
    case 2: return StopKind::QuickStopRamp;
    case 3: case 4: return StopKind::TorqueLimit;
    default: return StopKind::Coast;
  }
}

}  // namespace ecat::ds402
