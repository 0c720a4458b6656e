// Plant parameters by name, as a device file's DriveProfile lists them.
#include <array>
#include <cmath>
#include <string_view>

#include "ds402/plant.hpp"

namespace ecat::ds402 {

namespace {
struct Field {
  std::string_view name;
  double PlantParameters::*member;
  int sign;  // 1: must be > 0, 0: must be >= 0, -1: any value
};

constexpr std::array<Field, 28> kFields{{
    {"rotor_inertia", &PlantParameters::rotor_inertia, 1},
    {"load_inertia", &PlantParameters::load_inertia, 0},
    {"viscous_friction", &PlantParameters::viscous_friction, 0},
    {"coulomb_friction", &PlantParameters::coulomb_friction, 0},
    {"torque_constant", &PlantParameters::torque_constant, 1},
    {"rated_torque", &PlantParameters::rated_torque, 1},
    {"peak_torque", &PlantParameters::peak_torque, 1},
    {"rated_speed", &PlantParameters::rated_speed, 1},
    {"max_speed", &PlantParameters::max_speed, 1},
    {"current_time_constant", &PlantParameters::current_time_constant, 1},
    {"velocity_bandwidth", &PlantParameters::velocity_bandwidth, 1},
    {"position_gain", &PlantParameters::position_gain, 1},
    {"velocity_feed_forward", &PlantParameters::velocity_feed_forward, 0},
    {"sub_step", &PlantParameters::sub_step, 1},
    {"over_speed", &PlantParameters::over_speed, 1},
    {"over_torque_time", &PlantParameters::over_torque_time, 1},
    {"negative_limit_switch", &PlantParameters::negative_limit_switch, -1},
    {"positive_limit_switch", &PlantParameters::positive_limit_switch, -1},
    {"home_switch_low", &PlantParameters::home_switch_low, -1},
    {"home_switch_high", &PlantParameters::home_switch_high, -1},
    {"index_offset", &PlantParameters::index_offset, -1},
    {"probe1_low", &PlantParameters::probe1_low, -1},
    {"probe1_high", &PlantParameters::probe1_high, -1},
    {"probe2_low", &PlantParameters::probe2_low, -1},
    {"probe2_high", &PlantParameters::probe2_high, -1},
    {"initial_position", &PlantParameters::initial_position, -1},
    {"negative_hard_stop", &PlantParameters::negative_hard_stop, -1},
    {"positive_hard_stop", &PlantParameters::positive_hard_stop, -1},
}};
constexpr double kLimitRevolutions = 100;
constexpr double kHomeSwitchRevolutions[2] = {3, 4};
constexpr double kProbe1Revolutions[2] = {6, 7};
constexpr double kProbe2Revolutions[2] = {-7, -6};
}  // namespace

PlantParameters resolve_axis(PlantParameters p) noexcept {
  const double rev = p.encoder_resolution;
  auto place = [](double& v, double value) {
    if (std::isnan(v)) v = value;
  };
  place(p.negative_limit_switch, -kLimitRevolutions * rev);
  place(p.positive_limit_switch, kLimitRevolutions * rev);
  place(p.home_switch_low, kHomeSwitchRevolutions[0] * rev);
  place(p.home_switch_high, kHomeSwitchRevolutions[1] * rev);
  place(p.probe1_low, kProbe1Revolutions[0] * rev);
  place(p.probe1_high, kProbe1Revolutions[1] * rev);
  place(p.probe2_low, kProbe2Revolutions[0] * rev);
  place(p.probe2_high, kProbe2Revolutions[1] * rev);
  return p;
}

Expected<PlantParameters, std::string> plant_parameters_from(
    std::span<const std::pair<std::string, double>> values, PlantParameters base) {
  for (const auto& [name, value] : values) {
    if (name == "encoder_resolution") {
      if (!(value >= 1 && value <= 4294967295.0)) return fail(std::string("plant parameter encoder_resolution out of range"));
      base.encoder_resolution = static_cast<std::uint32_t>(value);
      continue;
    }
    bool found = false;
    for (const Field& f : kFields) {
      if (f.name != name) continue;
      found = true;
      if (!std::isfinite(value) || (f.sign > 0 && !(value > 0)) || (f.sign == 0 && value < 0)) {
        return fail("plant parameter " + name + " out of range");
      }
      base.*f.member = value;
    }
    if (!found) return fail("unknown plant parameter " + name);
  }
  base = resolve_axis(base);
  if (base.peak_torque < base.rated_torque) return fail(std::string("plant: peak_torque below rated_torque"));
  if (base.velocity_feed_forward > 1.0) return fail(std::string("plant: velocity_feed_forward above 1"));
  if (base.home_switch_low > base.home_switch_high) return fail(std::string("plant: home_switch_low above home_switch_high"));
  if (base.negative_limit_switch >= base.positive_limit_switch)
    return fail(std::string("plant: negative_limit_switch not below positive_limit_switch"));
  if (base.negative_hard_stop >= base.positive_hard_stop)
    return fail(std::string("plant: negative_hard_stop not below positive_hard_stop"));
  return base;
}

}  // namespace ecat::ds402
