// Drive: terminals and brake forced from outside (ds402/drive_overrides.hpp).
#include "ds402/drive_overrides.hpp"

#include "ds402/controlword.hpp"
#include "ds402/drive.hpp"
#include "ds402/drive_constants.hpp"

namespace ecat::ds402 {

using namespace detail;

namespace {
// 605Eh 0: disable drive function, the motor is free to rotate (CiA 402-2
// §8.4.7): what safe torque off does whatever 605Eh says.
constexpr std::int16_t kFaultReactionCoast = 0;
}  // namespace

void Drive::set_overrides(const DriveOverrides& o) noexcept {
  overrides_ = o;
  overridden_ = o.any();
  plant_.set_held(o.brake_stuck);
}

void Drive::apply_overrides(StateMachine::Inputs& si) noexcept {
  if (overrides_.safe_torque_off) {
    if ((latched_ & kSafeTorqueOffBit) == 0) {
      latched_ |= kSafeTorqueOffBit;
      latch(kSafeTorqueOffCode);
    }
    si.fault = true;
    si.fault_reaction_option = kFaultReactionCoast;  // no torque: no ramp is possible
  }
  // The quick-stop terminal acts as controlword bit 2 = 0 (CiA 402-2 §8.1.3
  // command "quick stop"): transition 11 from Operation enabled, 7/10 from
  // Ready to switch on / Switched on, and no enable while it is active.
  if (overrides_.quick_stop) si.controlword = static_cast<std::uint16_t>(si.controlword & ~cw::kQuickStop);
}

std::uint32_t Drive::forced_digital_inputs() const noexcept {
  std::uint32_t di = 0;
  if (overrides_.negative_limit) di |= kDiNegativeLimit;
  if (overrides_.positive_limit) di |= kDiPositiveLimit;
  return di;
}

}  // namespace ecat::ds402
