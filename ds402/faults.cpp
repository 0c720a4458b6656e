#include "ds402/faults.hpp"

namespace ecat::ds402 {

std::string_view to_string(FaultKind k) noexcept {
  switch (k) {
    case FaultKind::FollowingError: return "following error";
    case FaultKind::SoftwareLimit: return "software position limit";
    case FaultKind::PositiveLimitSwitch: return "positive limit switch";
    case FaultKind::NegativeLimitSwitch: return "negative limit switch";
    case FaultKind::OverSpeed: return "over-speed";
    case FaultKind::OverTorque: return "over-torque";
    case FaultKind::SyncLost: return "loss of synchronisation";
  }
  return "?";
}

}  // namespace ecat::ds402
