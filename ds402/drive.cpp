// Drive: the cycle, mode selection and entry.
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

Drive::Drive(DriveConfig config, const PlantParameters& plant)
    : config_(std::move(config)), plant_(resolve_axis(plant)), axis_(plant_.parameters()) {
  gen_.reset(plant_.position(), 0.0);
  demand_.position = plant_.position();
  moving_ = plant_.rpm_to_increments(kMovingRpm);
}

void Drive::update_scaling(const DriveInputs& in) noexcept {
  const ScalingInputs scaling{in.encoder_increments,     in.motor_revolutions, in.gear_motor_revolutions,
                              in.gear_shaft_revolutions, in.feed,              in.feed_shaft_revolutions,
                              in.vl_setpoint_numerator,  in.vl_setpoint_denominator, in.vl_dimension_numerator,
                              in.vl_dimension_denominator};
  if (scaling_set_ && scaling == scaling_inputs_) return;
  units_ = UnitScaling::from(in, plant_.parameters().encoder_resolution);
  vl_inc_per_unit_ = plant_.rpm_to_increments(VelocityMode::rpm_per_unit(in));
  vl_inc_per_setpoint_ = vl_inc_per_unit_ * VelocityMode::setpoint_factor(in);
  scaling_inputs_ = scaling;
  scaling_set_ = true;
}

void Drive::update_limits(const DriveInputs& in) noexcept {
  const LimitInputs limits{in.max_motor_speed, in.max_torque, in.positive_torque_limit, in.negative_torque_limit};
  if (limits_set_ && limits == limit_inputs_) return;
  const PlantParameters& pp = plant_.parameters();
  const double max_rpm = in.max_motor_speed ? static_cast<double>(in.max_motor_speed) : pp.max_speed;
  limits_.velocity = plant_.rpm_to_increments(max_rpm);
  limits_.torque_positive = std::min(pp.peak_torque, torque_nm(std::min(in.max_torque, in.positive_torque_limit)));
  limits_.torque_negative = std::min(pp.peak_torque, torque_nm(std::min(in.max_torque, in.negative_torque_limit)));
  limit_inputs_ = limits;
  limits_set_ = true;
}

void Drive::step(const DriveInputs& in, DriveOutputs& out, Nanoseconds cycle) noexcept {
  if (cycle != cycle_) {
    cycle_ = cycle;
    dt_ = std::chrono::duration<double>(cycle).count();
  }
  const double dt = dt_;
  if (!(dt > 0)) {  // no time passed: nothing moves, report as is
    fill(in, out, 0.0);
    return;
  }
  update_scaling(in);
  // The interpolation buffer (60C4h) takes records whatever the mode, so a
  // master can fill it before it enables interpolation.
  // A buffer without access is empty and takes nothing: its other settings
  // matter only once 60C4h:06 enables it (the common case: no 60C4h at all).
  ip_record_lost_ = false;
  if (in.ip_buffer_access != IpBuffer::kClear || ip_buffer_.enabled()) {
    ip_buffer_.configure(IpBuffer::Config{in.ip_buffer_actual_size, in.ip_buffer_organisation,
                                          in.ip_buffer_position, in.ip_buffer_access});
    const std::uint32_t lost_before = ip_buffer_.lost();
    if (in.ip_record_new) ip_buffer_.push(in.ip_position);
    ip_record_lost_ = ip_buffer_.lost() != lost_before;
  }
  controlword_ = in.controlword;
  halted_ = (in.controlword & cw::kHalt) != 0;
  internal_limit_ = false;

  // Transition 15 needs the faults cleared first (CiA 402-2 §8.1.3).
  // An external fault that is still present survives the reset.
  // So does safe torque off while its input is active.
  if (sm_.fault_reset_edge(in.controlword) && sm_.state() == PdsState::Fault && !external_ &&
      !overrides_.safe_torque_off) {
    clear_faults();
  }
  if (external_ && !external_fault_latched()) raise_external_fault(*external_);

  StateMachine::Inputs si;
  si.controlword = in.controlword;
  si.fault = latched_ != 0;
  si.motion_stopped = stopped_;
  si.quick_stop_option = config_.quick_stop.pick(in.quick_stop_option);
  si.shutdown_option = config_.shutdown.pick(in.shutdown_option);
  si.disable_operation_option = config_.disable_operation.pick(in.disable_operation_option);
  si.fault_reaction_option = config_.fault_reaction.pick(in.fault_reaction_option);
  if (overridden_) [[unlikely]] apply_overrides(si);
  const PdsState before = sm_.state();
  sm_.step(si);
  if (sm_.state() == PdsState::OperationEnabled && before != PdsState::OperationEnabled) enter_mode();

  select_mode(in);

  if (sm_.stop() == StopKind::None) stopping_ = false;
  if (!sm_.power_stage_on()) {
    demand_ = LoopDemand{};
    demand_.position = plant_.position();
    gen_.reset(plant_.position(), plant_.velocity());
    stopped_ = true;
  } else if (sm_.stop() != StopKind::None) {
    // A stop ramps down from the motion as it is, whatever the mode demanded.
    if (!stopping_) gen_.reset(plant_.position(), plant_.velocity());
    stopping_ = true;
    run_stop(sm_.stop(), in, dt);
  } else {
    run_mode(in, dt);
  }

  update_limits(in);  // after the modes: their stop ramps use the previous cycle's limits
  plant_.step(demand_, limits_, dt);

  probe_.cycle(in.touch_probe_function, axis_, plant_.previous_position(), plant_.position(), units_, home_shift_);
  monitor(in, dt);
  fill(in, out, dt);
  previous_controlword_ = in.controlword;
}

void Drive::select_mode(const DriveInputs& in) noexcept {
  const std::int8_t req = in.modes_of_operation;
  if (req == static_cast<std::int8_t>(mode_)) {
    warning_ = false;
    return;
  }
  if (req != 0 && !config_.supports_mode(req)) {
    warning_ = true;  // not taken: 6061h keeps showing the mode in use
    return;
  }
  warning_ = false;
  mode_ = static_cast<OperationMode>(req);
  if (sm_.state() == PdsState::OperationEnabled) enter_mode();
}

// A new mode (or enabling) starts from where the motor is.
void Drive::enter_mode() noexcept {
  if (homing_.active()) homing_.interrupt();
  gen_.reset(plant_.position(), plant_.velocity());
  pp_.enter(plant_.position());
  torque_demand_pm_ = torque_per_mille(plant_.torque());
  position_window_ = velocity_window_ = speed_zero_ = Timer{};
  demand_.position = plant_.position();
  ip_active_ = false;
  vl_.enter(plant_.velocity() / vl_inc_per_unit_);
}

}  // namespace ecat::ds402
