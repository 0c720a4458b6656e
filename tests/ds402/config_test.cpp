// Plant parameters by name, unit scaling and the drive personalities.
#include <gtest/gtest.h>

#include "ds402/drive_config.hpp"
#include "ds402/homing.hpp"
#include "ds402/plant.hpp"
#include "ds402/units.hpp"
#include "harness.hpp"

namespace ecat::ds402::test {
namespace {

TEST(PlantParameters, NamesSetFieldsAndBadInputIsAnError) {
  std::vector<std::pair<std::string, double>> v{{"rotor_inertia", 5e-5}, {"encoder_resolution", 1048576},
                                                {"home_switch_low", -10}, {"home_switch_high", 10}};
  auto p = plant_parameters_from(v);
  ASSERT_TRUE(p) << p.error();
  EXPECT_DOUBLE_EQ(p->rotor_inertia, 5e-5);
  EXPECT_EQ(p->encoder_resolution, 1048576u);
  EXPECT_DOUBLE_EQ(p->home_switch_low, -10);

  // Unset axis positions follow the encoder: limits at +-100 revolutions.
  EXPECT_DOUBLE_EQ(p->positive_limit_switch, 100.0 * 1048576);
  EXPECT_DOUBLE_EQ(p->probe1_low, 6.0 * 1048576);
  const PlantParameters d = resolve_axis(PlantParameters{});
  EXPECT_DOUBLE_EQ(d.negative_limit_switch, -100.0 * 131072);
  EXPECT_DOUBLE_EQ(d.home_switch_low, 3.0 * 131072);
  EXPECT_DOUBLE_EQ(d.home_switch_high, 4.0 * 131072);

  std::vector<std::pair<std::string, double>> unknown{{"rotor_inertai", 1}};
  EXPECT_EQ(plant_parameters_from(unknown).error(), "unknown plant parameter rotor_inertai");
  std::vector<std::pair<std::string, double>> negative{{"rated_torque", -1}};
  EXPECT_FALSE(plant_parameters_from(negative));
  std::vector<std::pair<std::string, double>> nan{{"viscous_friction", std::nan("")}};
  EXPECT_FALSE(plant_parameters_from(nan));
  std::vector<std::pair<std::string, double>> peak{{"peak_torque", 0.5}};
  EXPECT_EQ(plant_parameters_from(peak).error(), "plant: peak_torque below rated_torque");
  std::vector<std::pair<std::string, double>> zero_res{{"encoder_resolution", 0}};
  EXPECT_FALSE(plant_parameters_from(zero_res));
}

TEST(UnitScaling, FactorGroup) {
  DriveInputs in;
  EXPECT_DOUBLE_EQ(UnitScaling::from(in, 131072).increments_per_unit(), 1.0);
  // 10 mm lead screw in 0.001 mm units, 5:1 gear, 17-bit encoder.
  in.feed = 10000;
  in.feed_shaft_revolutions = 1;
  in.gear_motor_revolutions = 5;
  in.gear_shaft_revolutions = 1;
  const UnitScaling s = UnitScaling::from(in, 131072);
  EXPECT_DOUBLE_EQ(s.increments_per_unit(), 131072.0 * 5 / 10000);
  EXPECT_DOUBLE_EQ(s.to_user(s.to_increments(1234)), 1234);
}

TEST(UnitScaling, UserUnitsReachTheObjects) {
  Harness h;
  h.in.feed = 1000;  // 1000 units per motor revolution
  h.in.profile_velocity = 1000;
  h.in.profile_acceleration = 10000;
  h.in.profile_deceleration = 10000;
  h.in.position_window = 1;
  h.enable(OperationMode::ProfilePosition);
  h.in.target_position = 2000;  // two revolutions
  h.command(0x001F);
  h.command(0x000F);
  ASSERT_GT(h.run_until([&] { return (h.out.statusword & 0x0400) != 0; }, 5000), 0);
  h.run(100);
  EXPECT_NEAR(h.drive.plant().position(), 2 * 131072.0, 20);
  EXPECT_EQ(h.out.position_actual, 2000);
  EXPECT_NEAR(h.out.position_actual_internal, 262144, 150);
}

TEST(Personalities, ModesHomingAndOptionCodes) {
  ASSERT_EQ(personality_names().size(), 4u);
  for (auto name : personality_names()) EXPECT_TRUE(drive_personality(name)) << name;
  EXPECT_FALSE(drive_personality("acme"));
  const DriveConfig simtach = *drive_personality("simtach-rse");
  EXPECT_EQ(simtach.supported_modes, 0x3ADu);
  EXPECT_FALSE(simtach.supports_homing(1));
  EXPECT_TRUE(simtach.supports_homing(17));
  EXPECT_TRUE(simtach.supports_homing(35));
  EXPECT_FALSE(simtach.supports_homing(37));
  const DriveConfig yaskawa = *drive_personality("yaskawa-sigma5-sd");
  EXPECT_EQ(yaskawa.supported_modes, 0x3EDu);
  EXPECT_TRUE(yaskawa.supports_homing(24));
  EXPECT_FALSE(yaskawa.supports_homing(3));
  EXPECT_EQ(yaskawa.fault_reaction.pick(2), 0);
  const DriveConfig welcon = *drive_personality("welcon");
  EXPECT_EQ(welcon.supported_modes, 0x3AFu);
  EXPECT_TRUE(welcon.quick_stop.allows(6));
  EXPECT_FALSE(welcon.quick_stop.allows(3));
  EXPECT_EQ(welcon.quick_stop.pick(3), 6);
  const DriveConfig leadshine = *drive_personality("leadshine-isv2-can");
  EXPECT_EQ(leadshine.supported_modes, 0x2Du);
  EXPECT_FALSE(leadshine.supports_mode(8));
  EXPECT_FALSE(leadshine.quick_stop.allows(4));
  EXPECT_EQ(leadshine.fault_codes[static_cast<std::size_t>(FaultKind::FollowingError)].error_code, 0x8611);
}

TEST(Personalities, DeviceDescriptionOverrides) {
  od::DeviceDescription d;
  d.drive = od::DriveProfile{};
  d.drive->supported_modes = 0x25;  // PP, PV, HM
  d.drive->homing_methods = {35, 37};
  od::Object o;
  o.index = 0x605A;
  o.code = od::ObjectCode::Var;
  o.type = od::DataType::Integer16;
  od::Entry e;
  e.type = od::DataType::Integer16;
  e.bit_length = 16;
  e.default_value = {0x05, 0x00};
  e.min_value = {0x00, 0x00};
  e.max_value = {0x06, 0x00};
  o.entries.push_back(e);
  ASSERT_TRUE(d.dictionary.put(o));
  const DriveConfig c = apply_device(generic_drive(), d);
  EXPECT_EQ(c.supported_modes, 0x25u);
  EXPECT_TRUE(c.supports_homing(37));
  EXPECT_FALSE(c.supports_homing(1));
  EXPECT_TRUE(c.quick_stop.allows(6));
  EXPECT_FALSE(c.quick_stop.allows(7));
  EXPECT_EQ(c.quick_stop.default_value, 5);
}

TEST(HomingMethods, DefinedNumbersOnly) {
  for (int m : {0, 15, 16, 31, 32, 36, 38, -1, 127}) {
    EXPECT_FALSE(homing_method(static_cast<std::int8_t>(m))) << m;
  }
  for (int m = 1; m <= 14; ++m) EXPECT_TRUE(homing_method(static_cast<std::int8_t>(m))->index) << m;
  for (int m = 17; m <= 30; ++m) EXPECT_FALSE(homing_method(static_cast<std::int8_t>(m))->index) << m;
}

}  // namespace
}  // namespace ecat::ds402::test
