// The drive faults of slave::FaultCatalogue that act on a CiA 402 drive's
// terminals and brake (docs/faults.md "Drive"): a limit switch, the
// quick-stop input, safe torque off, a holding brake that does not release.
// Each sets or resets one ds402::DriveOverrides flag of the drive.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "common/expected.hpp"

namespace ecat::ds402 {
class Drive;
}

namespace ecat::slave::faults {

enum class DriveInput : std::uint8_t {
  LimitSwitch,     // limit_switch (side 0 negative, 1 positive)
  QuickStopInput,  // quick_stop_input
  SafeTorqueOff,   // sto
  BrakeStuck,      // brake_stuck
};

struct DriveInputFault {
  DriveInput input = DriveInput::LimitSwitch;
  bool positive = false;  // LimitSwitch: the side
};

// The fault of a catalogue kind name; nullopt for a kind that is not one of these.
std::optional<DriveInput> drive_input(std::string_view kind) noexcept;

// Checks `side` (limit_switch) and that the input is not already forced,
// then forces it; nothing changes when a check fails.
Expected<DriveInputFault, std::string> engage(DriveInput input, std::string_view kind, ds402::Drive& drive,
                                              const std::map<std::string, std::int64_t>& params);
// Releases it again (the drive reacts in its next step).
void clear(const DriveInputFault& fault, ds402::Drive& drive) noexcept;

}  // namespace ecat::slave::faults
