// Drive: monitoring and faults (603Fh, 1001h, EMCY requests).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "ds402/controlword.hpp"
#include "ds402/drive.hpp"
#include "ds402/drive_constants.hpp"
#include "ds402/statusword.hpp"

namespace ecat::ds402 {

using namespace detail;

void Drive::raise_fault(FaultKind k) noexcept {
  const std::uint32_t bit = 1u << static_cast<unsigned>(k);
  if (latched_ & bit) return;
  latched_ |= bit;
  latch(config_.fault_codes[static_cast<std::size_t>(k)]);
}

void Drive::raise_external_fault(const FaultCode& code) noexcept {
  latched_ |= kExternalFaultBit;
  latch(code);
}

void Drive::latch(const FaultCode& code) noexcept {
  error_code_ = code.error_code;
  error_register_ = static_cast<std::uint8_t>(error_register_ | error_register::kGeneric | code.error_register);
  EmcyRequest r;
  r.error_code = config_.emcy_code.value_or(code.error_code);
  r.error_register = error_register_;
  if (config_.emcy_code) {  // alarm number in EMCY bytes 4-5
    r.manufacturer[1] = static_cast<std::uint8_t>(code.error_code);
    r.manufacturer[2] = static_cast<std::uint8_t>(code.error_code >> 8);
  }
  emcy_.push(r);
}

void Drive::clear_faults() noexcept {
  latched_ = 0;
  error_code_ = 0;
  error_register_ = 0;
  following_error_ = false;
  following_timer_ = torque_timer_ = Timer{};
  emcy_.push(EmcyRequest{kEmcyErrorReset, 0, {}});
}

void Drive::monitor(const DriveInputs& in, double dt) noexcept {
  const PlantParameters& p = plant_.parameters();
  const bool driving = sm_.power_stage_on();
  const bool operating = sm_.operation_active();
  const double pos = plant_.position();
  const double v = plant_.velocity();
  const double moving = moving_;

  // Following error (6065h/6066h, CiA 402-2 §12.4.2).
  if (driving && demand_.kind == LoopDemand::Kind::Position && in.following_error_window != kFollowingErrorOff) {
    const double error = std::abs(to_user(demand_.position - pos));
    following_error_ = following_timer_.update(error > in.following_error_window, dt,
                                               in.following_error_timeout / kMsPerS);
    if (following_error_) raise_fault(FaultKind::FollowingError);
  } else {
    following_error_ = false;
    following_timer_ = Timer{};
  }
  // Hardware limit switches, outside homing: moving into one is a fault.
  if (operating && mode_ != OperationMode::Homing) {
    const bool positive = overrides_.positive_limit || axis_.active(AxisSignal::PositiveLimit, pos);
    const bool negative = overrides_.negative_limit || axis_.active(AxisSignal::NegativeLimit, pos);
    if (positive && v > moving) raise_fault(FaultKind::PositiveLimitSwitch);
    if (negative && v < -moving) raise_fault(FaultKind::NegativeLimitSwitch);
  }
  // Software limits (607Dh) in the modes that do not clip their targets.
  const bool clipping = mode_ == OperationMode::ProfilePosition || mode_ == OperationMode::Homing ||
                        mode_ == OperationMode::CyclicSyncPosition ||
                        mode_ == OperationMode::InterpolatedPosition;
  if (operating && !clipping && in.software_limit_min < in.software_limit_max) {
    const double u = position_to_user(pos);
    if ((u > in.software_limit_max && v > moving) || (u < in.software_limit_min && v < -moving)) {
      raise_fault(FaultKind::SoftwareLimit);
    }
  }
  if (std::abs(plant_.increments_to_rpm(v)) > p.over_speed) raise_fault(FaultKind::OverSpeed);
  if (torque_timer_.update(driving && plant_.torque_limited(), dt, p.over_torque_time)) {
    raise_fault(FaultKind::OverTorque);
  }
  if (in.sync_lost && driving) raise_fault(FaultKind::SyncLost);
}

}  // namespace ecat::ds402
