// The simulated servo axis: a rigid rotor plus load with viscous and Coulomb
// friction, driven by a torque (current) loop modelled as a first-order lag,
// under a cascaded velocity PI and position P controller (the usual servo
// structure, CiA 402-2 Figure 3/§12). The controller is sampled: everything
// runs in fixed sub-steps of one drive cycle, so the result depends only on
// the inputs (deterministic). Where no limit, clamp or friction switch acts
// during a cycle the sub-step model is linear, and its n sub-steps are
// applied at once in closed form (docs/ds402.md, "The plant").
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <utility>

#include "common/expected.hpp"

namespace ecat::ds402 {

// Parameters of the motor, the load and the controller. The device file's
// DriveProfile "plant" name/value pairs set them by the names in kPlantNames
// (docs/ds402.md lists them). Defaults: a 400 W, 3000 rpm servo with a
// 17-bit encoder and a load of three times the rotor inertia.
struct PlantParameters {
  static constexpr double kUnset = std::numeric_limits<double>::quiet_NaN();

  // The members every cycle reads come first, in one cache line for both
  // copies (the Plant's and the Axis's; issue 30 item 1): the limit
  // switches (Axis), then the friction, torque, encoder and monitoring
  // figures (Plant, Drive). The order is the layout's only: the XML names
  // map by member (plant_parameters.cpp).
  //
  // The axis: switch and mark positions in encoder increments (motor side).
  // Left unset (NaN) they are placed by motor revolutions, whatever the
  // encoder (resolve_axis): limit switches at -100/+100 rev, home switch
  // over [3, 4] rev, probe 1 input over [6, 7] rev, probe 2 over [-7, -6] rev.
  double negative_limit_switch = kUnset;  // active at or below  "negative_limit_switch"
  double positive_limit_switch = kUnset;  // active at or above  "positive_limit_switch"
  double coulomb_friction = 0.02;         // N·m            "coulomb_friction"
  double rated_torque = 1.27;             // N·m            "rated_torque"
  std::uint32_t encoder_resolution = 131072;  // inc/rev   "encoder_resolution"
  double velocity_feed_forward = 0.0;     // 0..1           "velocity_feed_forward"
  // Monitoring thresholds.
  double over_speed = 6000;            // rpm              "over_speed"
  double over_torque_time = 0.5;       // s at the torque limit  "over_torque_time"

  double rotor_inertia = 3.4e-5;          // kg·m²          "rotor_inertia"
  double load_inertia = 1.0e-4;           // kg·m²          "load_inertia"
  double viscous_friction = 1.0e-4;       // N·m/(rad/s)    "viscous_friction"
  double torque_constant = 0.45;          // N·m/A          "torque_constant"
  double peak_torque = 3.82;              // N·m            "peak_torque"
  double rated_speed = 3000;              // rpm            "rated_speed"
  double max_speed = 5000;                // rpm            "max_speed"
  double current_time_constant = 2.0e-4;  // s              "current_time_constant"
  double velocity_bandwidth = 150;        // Hz             "velocity_bandwidth"
  double position_gain = 100;             // 1/s            "position_gain"
  double sub_step = 62.5e-6;              // s, longest integration step "sub_step"

  // The other marks (see the limit switches above).
  double home_switch_low = kUnset;        // active in [low, high] "home_switch_low"
  double home_switch_high = kUnset;       //                       "home_switch_high"
  double index_offset = 1000;             // index pulse at k·resolution + offset "index_offset"
  double probe1_low = kUnset;             // touch probe 1 input active in [low, high] "probe1_low"
  double probe1_high = kUnset;            //                                       "probe1_high"
  double probe2_low = kUnset;             // "probe2_low"
  double probe2_high = kUnset;            // "probe2_high"
  double initial_position = 0;            // increments at power-on "initial_position"
  // Mechanical end stops (increments; NaN: none): the rotor cannot pass them
  // and stops dead there (velocity 0), the controller then pushes against
  // them. Used by the current-threshold homing methods (Welcon -3/-4).
  double negative_hard_stop = kUnset;     // "negative_hard_stop"
  double positive_hard_stop = kUnset;     // "positive_hard_stop"

  double total_inertia() const noexcept { return rotor_inertia + load_inertia; }
};

// Places every unset axis position by motor revolutions (see above).
PlantParameters resolve_axis(PlantParameters p) noexcept;

// Sets the named parameters; an unknown name or a value out of its sensible
// range is an error naming it.
Expected<PlantParameters, std::string> plant_parameters_from(
    std::span<const std::pair<std::string, double>> values, PlantParameters base = {});

// What the controller follows during one cycle.
struct LoopDemand {
  enum class Kind : std::uint8_t { Off, Position, Velocity, Torque };
  Kind kind = Kind::Off;
  double position = 0;  // increments, at the end of the cycle (linear in between)
  double velocity = 0;  // increments/s: demand (Velocity) or profile velocity (Position),
                        // fed forward scaled by velocity_feed_forward
  double torque = 0;    // N·m: demand (Torque) or feed-forward
  double velocity_offset = 0;  // increments/s added to the velocity command (60B1h)
};

struct LoopLimits {
  double torque_positive = 0;  // N·m, >= 0
  double torque_negative = 0;  // N·m, >= 0 (magnitude)
  double velocity = 0;         // increments/s, >= 0
};

class Plant {
 public:
  explicit Plant(const PlantParameters& p) noexcept;

  // How the last step() was computed (the result is the same either way, up
  // to floating-point rounding): the state was the exact rest point, the
  // sub-steps were linear and applied in closed form, the rotor stood held
  // by friction throughout (closed form of the controller alone), or they
  // were run one by one (a clamp or a friction switch in play).
  enum class Path : std::uint8_t { Rest, ClosedForm, Standstill, SubSteps };

  // Advances by `dt` seconds in equal sub-steps no longer than sub_step.
  void step(const LoopDemand& demand, const LoopLimits& limits, double dt) noexcept;
  // The same, always one sub-step after the other: the reference the
  // closed-form and rest paths are tested against.
  void step_by_sub_steps(const LoopDemand& demand, const LoopLimits& limits, double dt) noexcept;
  // Whether the last step ended on an end stop (clamped there).
  bool at_hard_stop() const noexcept { return at_hard_stop_; }
  Path last_path() const noexcept { return last_path_; }

  // A load torque acting against the motor (N·m), e.g. a stall or collision.
  void set_external_torque(double nm) noexcept { external_torque_ = nm; }
  // A holding brake that does not release (fault brake_stuck): the rotor
  // stays where it is whatever torque the motor produces.
  void set_held(bool held) noexcept { held_ = held; }
  bool held() const noexcept { return held_; }

  double position() const noexcept { return position_; }  // increments
  double velocity() const noexcept { return velocity_; }  // increments/s
  double torque() const noexcept { return torque_; }      // N·m produced
  double torque_command() const noexcept { return torque_command_; }
  bool torque_limited() const noexcept { return torque_limited_; }
  const PlantParameters& parameters() const noexcept { return p_; }

  // Increments/s of `rpm`, and back.
  double rpm_to_increments(double rpm) const noexcept { return rpm * p_.encoder_resolution / 60.0; }
  double increments_to_rpm(double v) const noexcept { return v * 60.0 / p_.encoder_resolution; }

  // Position at the start of the last step (for edge detection).
  double previous_position() const noexcept { return previous_position_; }

  // The closed-form table the last steps used (null before it is built for
  // the current cycle length). Plants whose table inputs (parameters and
  // cycle length) are equal share one (see ClosedForms).
  const void* closed_forms() const noexcept { return closed_forms_.get(); }

 private:
  // The sub-step model of the position/velocity loops while it is linear:
  // state s = (E, v, T, I) with E = position reference at the start of the
  // sub-step minus position (0 in velocity mode), v velocity, T torque, I
  // velocity integral; constant inputs u = (dr, cv, tff, dist): reference
  // increment per sub-step, velocity command offset, torque feed-forward,
  // -(external + Coulomb) torque. One sub-step is s' = A s + B u, so over
  // the n sub-steps of a cycle s_i = ss + A^i (s_0 - ss) with the steady
  // state ss = A ss + B u (closed_form() writes it out). Built once per
  // cycle length.
  struct Linear {
    double phi[4][4];   // A^n
    double travel[4];   // position change of the cycle per unit of s_0 - ss
    double tc_end[4];   // torque command of the last sub-step per unit of s_0 - ss
    // max over the sub-steps of |coefficient| of s_0 - ss in the velocity
    // command, the torque command and the velocity: bounds of how far the
    // transient takes them from their steady value.
    double vcmd_bound[4];
    double tc_bound[4];
    double v_bound[4];
    // Second bounds, tight when the transient is slow against the cycle:
    // each quantity stays within its first and last sub-step's values, plus
    // max over the sub-steps of |coefficient| of the distance from the
    // straight line between those two (chord). vcmd_last: the velocity
    // command of the last sub-step per unit of s_0 - ss (tc_end and phi[1]
    // are the others' last values).
    double vcmd_last[4];
    double vcmd_chord[4];
    double tc_chord[4];
    double v_chord[4];
    bool valid;  // false: a zero-length cycle or an overflowing A^n; always sub-steps
  };
  // The three closed forms of one cycle length. They depend only on the
  // parameters and the cycle length, so plants with equal inputs share one
  // immutable table (issue 16 item 5: 1,272 bytes per drive otherwise): built
  // by the first plant that needs it, kept while a plant uses it
  // (shared_closed_forms, plant.cpp).
  struct ClosedForms {
    Linear position_loop;
    Linear velocity_loop;
    Linear torque_loop;  // state (0, v, T, 0): the torque modes' lag and mechanics
  };
  // The standstill closed form: over n sub-steps of the torque lag,
  // T_n = decay·T_0 + Σ_k weight_k·tc_k with tc_k = c0 + c1·k + c2·k².
  struct Standstill {
    double decay;      // (1 - λ)^n
    double weight[3];  // Σ_k λ(1 - λ)^(n-k)·k^m, m = 0, 1, 2
  };
  bool standstill(const LoopDemand& d, const LoopLimits& lim, double start_ref) noexcept;
  void configure(double dt) noexcept;
  void build_closed_forms() noexcept;
  std::shared_ptr<const ClosedForms> shared_closed_forms() const;
  void build_standstill() noexcept;
  void build_linear(Linear& m, LoopDemand::Kind mode) const noexcept;
  void linear_sub_step(double s[4], const double u[4], LoopDemand::Kind mode) const noexcept;
  bool at_rest(const LoopDemand& d, const LoopLimits& lim, double start_ref) noexcept;
  bool closed_form(const LoopDemand& d, const LoopLimits& lim, double start_ref) noexcept;
  bool closed_form_torque(const LoopDemand& d, const LoopLimits& lim) noexcept;
  void run_sub_steps(const LoopDemand& d, const LoopLimits& lim, double start_ref) noexcept;
  void sub_step(const LoopDemand& d, const LoopLimits& lim, double position_ref, double h) noexcept;

  // The state and what a cycle reads with it first, then the parameters
  // (whose fields a cycle reads are in PlantParameters' first lines): one
  // drive's cycle reads four lines of the plant instead of six (issue 30
  // item 1: at 1000 drives each is a cache miss).
  double position_ = 0;
  double previous_position_ = 0;
  double velocity_ = 0;
  double torque_ = 0;
  double torque_command_ = 0;
  double integral_ = 0;
  double external_torque_ = 0;
  double last_position_ref_ = 0;
  bool last_was_position_ = false;
  bool torque_limited_ = false;
  bool at_hard_stop_ = false;
  bool held_ = false;  // set_held: the brake holds the rotor
  bool has_hard_stops_ = false;  // either end stop is set (not NaN)
  void apply_hard_stops() noexcept;
  Path last_path_ = Path::SubSteps;
  // Set by configure() for the cycle length dt_ it was last called with (the
  // cycle time rarely changes, so exp() and the divisions run once per new
  // cycle time): n_ sub-steps of h_, the current-loop lag factor
  // 1 - exp(-h/tau); the closed-form models are built when that cycle time
  // comes a second time in a row (closed_forms_), the standstill weights
  // when first needed.
  double dt_ = -1;
  std::shared_ptr<const ClosedForms> closed_forms_;  // for dt_; null: not built yet
  PlantParameters p_;
  double rad_per_inc_;
  double kv_;  // velocity P gain, N·m per increment/s
  double ki_;  // velocity I gain, N·m per increment
  int n_ = 1;
  double h_ = 0;
  double inv_n_ = 1;
  double lag_factor_ = 0;
  bool standstill_ready_ = false;  // standstill_ is for dt_
  Standstill standstill_{};
};

}  // namespace ecat::ds402
