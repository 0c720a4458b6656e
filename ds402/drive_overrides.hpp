// Signals from outside the drive's command path that a fault injection sets
// (slave::FaultCatalogue limit_switch, quick_stop_input, sto, brake_stuck;
// docs/faults.md "Drive"): the terminals of a real servo drive - limit
// switch inputs, a quick-stop input, the safe-torque-off input - and a
// holding brake that does not release. Drive::set_overrides applies them
// from the next step on; with none set the drive's cycle tests one flag.
#pragma once

#include <cstdint>

#include "ds402/faults.hpp"

namespace ecat::ds402 {

struct DriveOverrides {
  // 60FDh bits 0 (negative) / 1 (positive) forced active whatever the axis
  // position: statusword bit 11 while one is active, and motion into it is
  // the drive's limit-switch fault (FF04h / FF03h, as on the simulated axis).
  bool negative_limit = false;
  bool positive_limit = false;
  // An external quick stop: controlword bit 2 reads 0 for the PDS state
  // machine, so it stops per 605Ah (Operation enabled -> Quick stop active)
  // and cannot be enabled again while the input is active.
  bool quick_stop = false;
  // Safe torque off: no torque at once (the motor coasts), Fault with
  // kSafeTorqueOffCode and its EMCY; a fault reset leaves it in Fault while
  // the input is active.
  bool safe_torque_off = false;
  // The holding brake does not release: the rotor cannot turn.
  bool brake_stuck = false;

  bool any() const noexcept {
    return negative_limit || positive_limit || quick_stop || safe_torque_off || brake_stuck;
  }
  bool operator==(const DriveOverrides&) const = default;
};

// 603Fh / EMCY code of safe torque off: CiA 402-2's 5441h ("contact 1", the
// drive-enable input class the Leadshine seed manual uses for its emergency
// stop input, alarm 570), device-profile class in 1001h (docs/faults.md).
inline constexpr FaultCode kSafeTorqueOffCode{0x5441, error_register_for(0x5441)};

}  // namespace ecat::ds402
