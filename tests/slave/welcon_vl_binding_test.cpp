// The dual-axis Welcon file's vl objects and homing threshold reach each
// axis' drive through its binding (issue 15): 6042h-6051h (+800h for axis 2)
// from xml/profiles/cia402-vl.xml, 2402h/2C02h, and 6043h/6044h written back;
// one axis in vl leaves the other alone.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "ds402/drive.hpp"
#include "ds402/od_binding.hpp"
#include "esi/device_loader.hpp"
#include "tests/coe/rig.hpp"

namespace ecat::ds402 {
namespace {

constexpr Nanoseconds kCycle = std::chrono::milliseconds(1);

TEST(WelconVlBinding, Axis2RunsVlFromItsOwnObjects) {
  auto dev = esi::load_device_file(std::string(ECAT_SOURCE_DIR) + "/xml/devices/welcon-servo-dual.xml");
  ASSERT_TRUE(dev.has_value()) << dev.error().to_string();
  for (int i : {0x6042, 0x6043, 0x6044, 0x6046, 0x6048, 0x6049, 0x604A, 0x604B, 0x604C, 0x604D, 0x604E, 0x604F,
                0x6050, 0x6051}) {
    EXPECT_NE(dev->dictionary.find(static_cast<std::uint16_t>(i)), nullptr) << std::hex << i;
    EXPECT_NE(dev->dictionary.find(static_cast<std::uint16_t>(i + 0x800)), nullptr) << std::hex << i + 0x800;
  }
  coe::test::Rig rig(*dev);
  const DriveConfig config = apply_device(*drive_personality("welcon"), *dev);
  EXPECT_TRUE(config.supports_mode(2));
  EXPECT_TRUE(config.supports_homing(-3));
  auto plant = plant_parameters_from(dev->drive->plant);
  ASSERT_TRUE(plant.has_value());
  DriveBinding b1(rig.store, nullptr, dev->drive->axes, 1), b2(rig.store, nullptr, dev->drive->axes, 2);
  b1.publish(config);
  b2.publish(config);
  Drive d1(config, *plant), d2(config, *plant);
  // vl on axis 2: 6860h = 2 passes the SDO check (6502h lists vl).
  const std::vector<std::uint8_t> vl{2};
  ASSERT_TRUE(rig.store.write(coe::WriteRequest{0x6860, 0, vl, od::EsmState::Op}));
  ASSERT_TRUE(rig.store.set<std::int16_t>(0x6842, 0, 300));
  ASSERT_TRUE(rig.store.set<std::uint32_t>(0x6848, 1, 1000));  // 1000 rpm per 1 s
  ASSERT_TRUE(rig.store.set<std::uint16_t>(0x6848, 2, 1));
  ASSERT_TRUE(rig.store.set<std::uint32_t>(0x2C02, 0, 250));
  DriveInputs in1, in2;
  DriveOutputs out1, out2;
  EmcyQueue q1, q2;
  auto cycle = [&](std::uint16_t cw2) {
    ASSERT_TRUE(rig.store.set<std::uint16_t>(0x6840, 0, cw2));
    b1.read_cycle(in1, {});
    b2.read_cycle(in2, {});
    d1.step(in1, out1, kCycle);
    d2.step(in2, out2, kCycle);
    b1.write_axis(out1, q1, Nanoseconds{0}, out2.error_register);
    b2.write_axis(out2, q2, Nanoseconds{0}, out1.error_register);
  };
  cycle(0x0000);  // not ready to switch on -> switch on disabled
  cycle(0x0006);
  cycle(0x0007);
  cycle(0x000F);
  EXPECT_EQ(in2.homing_current_threshold, 250u);
  EXPECT_EQ(in1.homing_current_threshold, 100u);  // 2402h's default
  EXPECT_EQ(rig.store.get<std::int8_t>(0x6861, 0), 2);
  EXPECT_EQ(rig.store.get<std::uint16_t>(0x6841, 0) & 0x027F, 0x0237);  // operation enabled
  for (int i = 0; i < 100; ++i) cycle(0x007F);
  EXPECT_EQ(rig.store.get<std::int16_t>(0x6843, 0), 100);  // 1 rpm per cycle
  EXPECT_EQ(rig.store.get<std::int16_t>(0x6043, 0), 0);
  for (int i = 0; i < 500; ++i) cycle(0x007F);
  EXPECT_EQ(rig.store.get<std::int16_t>(0x6843, 0), 300);
  EXPECT_EQ(rig.store.get<std::int16_t>(0x6844, 0), 300);
  EXPECT_NE(rig.store.get<std::uint16_t>(0x6841, 0) & 0x0400, 0);  // target reached
  EXPECT_EQ(rig.store.get<std::int32_t>(0x606C, 0), 0);            // axis 1 stands
  EXPECT_NEAR(rig.store.get<std::int32_t>(0x686C, 0), 300 * 10000 / 60, 20);  // 10000 inc/rev
}

}  // namespace
}  // namespace ecat::ds402
