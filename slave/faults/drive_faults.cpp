#include "slave/faults/drive_faults.hpp"

#include <fmt/format.h>

#include "ds402/drive.hpp"

namespace ecat::slave::faults {

namespace {

// The flag of one fault in the drive's overrides.
bool& flag(ds402::DriveOverrides& o, const DriveInputFault& f) noexcept {
  switch (f.input) {
    case DriveInput::LimitSwitch: return f.positive ? o.positive_limit : o.negative_limit;
    case DriveInput::QuickStopInput: return o.quick_stop;
    case DriveInput::SafeTorqueOff: return o.safe_torque_off;
    case DriveInput::BrakeStuck: return o.brake_stuck;
  }
  return o.brake_stuck;
}

}  // namespace

std::optional<DriveInput> drive_input(std::string_view kind) noexcept {
  if (kind == "limit_switch") return DriveInput::LimitSwitch;
  if (kind == "quick_stop_input") return DriveInput::QuickStopInput;
  if (kind == "sto") return DriveInput::SafeTorqueOff;
  if (kind == "brake_stuck") return DriveInput::BrakeStuck;
  return std::nullopt;
}

Expected<DriveInputFault, std::string> engage(DriveInput input, std::string_view kind, ds402::Drive& drive,
                                              const std::map<std::string, std::int64_t>& params) {
  DriveInputFault f;
  f.input = input;
  if (input == DriveInput::LimitSwitch) {
    const auto it = params.find("side");
    const std::int64_t side = it == params.end() ? -1 : it->second;
    if (side != 0 && side != 1) return fail(fmt::format("{}: side = {} is out of range (0 negative, 1 positive)", kind, side));
    f.positive = side == 1;
  }
  ds402::DriveOverrides o = drive.overrides();
  bool& on = flag(o, f);
  if (on) return fail(fmt::format("{}: that input of the drive is already forced", kind));
  on = true;
  drive.set_overrides(o);
  return f;
}

void clear(const DriveInputFault& fault, ds402::Drive& drive) noexcept {
  ds402::DriveOverrides o = drive.overrides();
  flag(o, fault) = false;
  drive.set_overrides(o);
}

}  // namespace ecat::slave::faults
