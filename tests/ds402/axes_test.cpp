// Several axes on one object store (issue 15, docs/ds402.md "Several axes"):
// each DriveBinding binds its own axis' objects (+800h per axis, CiA 402-1
// §6), publishes and guards that axis' 6502h/60E3h/6060h; two drives stepped
// together give exactly the outputs each gives alone; 1001h is the device's
// and the EMCY names its axis in byte 3.
#include <gtest/gtest.h>

#include "ds402/drive.hpp"
#include "ds402/od_binding.hpp"
#include "tests/coe/rig.hpp"

namespace ecat::ds402 {
namespace {

constexpr std::uint16_t kAxisOffset = 0x800;

od::Entry entry(std::uint8_t sub, od::DataType type, std::uint16_t bits, od::Value def = {}) {
  od::Entry e;
  e.subindex = sub;
  e.type = type;
  e.bit_length = bits;
  e.access.bits = od::Access::kRw;
  e.default_value = std::move(def);
  return e;
}

void var(od::Dictionary& d, std::uint16_t index, od::DataType type, std::uint16_t bits, od::Value def = {}) {
  od::Object o;
  o.index = index;
  o.code = od::ObjectCode::Var;
  o.type = type;
  o.entries.push_back(entry(0, type, bits, std::move(def)));
  ASSERT_TRUE(d.put(o));
}

void array(od::Dictionary& d, std::uint16_t index, od::DataType type, std::uint16_t bits, std::uint8_t n) {
  od::Object o;
  o.index = index;
  o.code = od::ObjectCode::Array;
  o.type = type;
  o.entries.push_back(entry(0, od::DataType::Unsigned8, 8, {n}));
  for (std::uint8_t s = 1; s <= n; ++s) o.entries.push_back(entry(s, type, bits));
  ASSERT_TRUE(d.put(o));
}

// A servo's objects once (axes = 1) or per axis at +800h, 1001h common.
od::DeviceDescription servo(unsigned axes) {
  using T = od::DataType;
  od::DeviceDescription dev;
  auto& d = dev.dictionary;
  var(d, 0x1001, T::Unsigned8, 8);
  for (unsigned a = 0; a < axes; ++a) {
    const auto o = static_cast<std::uint16_t>(a * kAxisOffset);
    var(d, 0x603F + o, T::Unsigned16, 16);
    var(d, 0x6040 + o, T::Unsigned16, 16);
    var(d, 0x6041 + o, T::Unsigned16, 16);
    var(d, 0x605A + o, T::Integer16, 16, {0x02, 0x00});
    var(d, 0x6060 + o, T::Integer8, 8);
    var(d, 0x6061 + o, T::Integer8, 8);
    var(d, 0x6064 + o, T::Integer32, 32);
    var(d, 0x6065 + o, T::Unsigned32, 32, {0x10, 0x27, 0, 0});  // 10000
    var(d, 0x606C + o, T::Integer32, 32);
    var(d, 0x607A + o, T::Integer32, 32);
    var(d, 0x6081 + o, T::Unsigned32, 32, {0x40, 0x9C, 0, 0});  // 40000
    var(d, 0x6083 + o, T::Unsigned32, 32, {0x80, 0x1A, 0x06, 0});  // 400000
    var(d, 0x6084 + o, T::Unsigned32, 32, {0x80, 0x1A, 0x06, 0});
    var(d, 0x6098 + o, T::Integer8, 8);
    array(d, 0x60E3 + o, T::Integer16, 16, 4);
    var(d, 0x6502 + o, T::Unsigned32, 32);
  }
  dev.drive = od::DriveProfile{};
  dev.drive->axes.axes = axes;
  return dev;
}

TEST(DriveAxes, EachBindingUsesItsAxisObjects) {
  const od::DeviceDescription dev = servo(2);
  coe::test::Rig rig(dev);
  DriveBinding one(rig.store, nullptr, dev.drive->axes, 1);
  DriveBinding two(rig.store, nullptr, dev.drive->axes, 2);
  EXPECT_EQ(one.bound_inputs(), two.bound_inputs());
  EXPECT_EQ(one.bound_outputs(), two.bound_outputs());
  two.publish(*drive_personality("yaskawa-sigma5-sd"));
  one.publish(*drive_personality("welcon"));
  EXPECT_EQ(rig.store.get<std::uint32_t>(0x6502, 0), 0x3AFu);
  EXPECT_EQ(rig.store.get<std::uint32_t>(0x6D02, 0), 0x3EDu);
  EXPECT_EQ(rig.store.get<std::int16_t>(0x68E3, 3), 7);  // Yaskawa: 1, 2, 7, 8
  EXPECT_EQ(rig.store.get<std::int16_t>(0x60E3, 1), -4);  // Welcon personality: -4, -3, 1, 2, 3, ...
  EXPECT_EQ(rig.store.get<std::int16_t>(0x60E3, 4), 2);
  ASSERT_TRUE(rig.store.set<std::uint16_t>(0x6840, 0, 0x000F));
  ASSERT_TRUE(rig.store.set<std::int32_t>(0x687A, 0, -4321));
  DriveInputs in1, in2;
  one.read(in1);
  two.read(in2);
  EXPECT_EQ(in1.controlword, 0);
  EXPECT_EQ(in2.controlword, 0x000F);
  EXPECT_EQ(in1.target_position, 0);
  EXPECT_EQ(in2.target_position, -4321);
  DriveOutputs out;
  out.statusword = 0x0237;
  out.error_register = 0x21;
  EmcyQueue none;
  two.write_axis(out, none, Nanoseconds{0}, 0x80);
  EXPECT_EQ(rig.store.get<std::uint16_t>(0x6841, 0), 0x0237);
  EXPECT_EQ(rig.store.get<std::uint16_t>(0x6041, 0), 0);
  EXPECT_EQ(rig.store.get<std::uint8_t>(0x1001, 0), 0xA1);  // this axis' bits and the others'
  // The SDO checks: axis 2 is a Yaskawa personality here (no VL), axis 1 a Welcon (605Ah 3 refused).
  const std::vector<std::uint8_t> vl{2}, qs3{3, 0};
  EXPECT_TRUE(rig.store.write(coe::WriteRequest{0x6060, 0, vl, od::EsmState::PreOp}));
  EXPECT_EQ(rig.store.write(coe::WriteRequest{0x6860, 0, vl, od::EsmState::PreOp}).error(), coe::SdoAbort::ValueRange);
  EXPECT_EQ(rig.store.write(coe::WriteRequest{0x605A, 0, qs3, od::EsmState::PreOp}).error(), coe::SdoAbort::ValueRange);
  EXPECT_TRUE(rig.store.write(coe::WriteRequest{0x685A, 0, qs3, od::EsmState::PreOp}));
}

// Enable and a PP move per axis (different targets), through the store.
void command(coe::ObjectStore& s, std::uint16_t offset, int cycle, std::int32_t target) {
  std::uint16_t cw = 0;
  if (cycle >= 2) cw = 0x0006;
  if (cycle >= 5) cw = 0x0007;
  if (cycle >= 8) cw = 0x000F;
  if (cycle >= 12 && cycle < 20) cw = 0x001F;  // new set-point
  ASSERT_TRUE(s.set<std::uint16_t>(0x6040 + offset, 0, cw));
  ASSERT_TRUE(s.set<std::int8_t>(0x6060 + offset, 0, 1));
  ASSERT_TRUE(s.set<std::int32_t>(0x607A + offset, 0, target));
}

TEST(DriveAxes, TwoAxesTogetherGiveExactlyWhatEachGivesAlone) {
  const od::DeviceDescription dual = servo(2), single = servo(1);
  coe::test::Rig both(dual), alone1(single), alone2(single);
  const std::array<std::int32_t, 2> target{30000, -17000};
  DriveBinding b1(both.store, nullptr, dual.drive->axes, 1), b2(both.store, nullptr, dual.drive->axes, 2);
  DriveBinding s1(alone1.store), s2(alone2.store);
  Drive d1(generic_drive(), PlantParameters{}), d2(generic_drive(), PlantParameters{});
  Drive e1(generic_drive(), PlantParameters{}), e2(generic_drive(), PlantParameters{});
  DriveInputs i1, i2, j1, j2;
  DriveOutputs o1, o2, p1, p2;
  EmcyQueue q;
  constexpr Nanoseconds kCycle = std::chrono::milliseconds(1);
  for (int c = 0; c < 1500; ++c) {
    command(both.store, 0, c, target[0]);
    command(both.store, kAxisOffset, c, target[1]);
    command(alone1.store, 0, c, target[0]);
    command(alone2.store, 0, c, target[1]);
    b1.read(i1), b2.read(i2), s1.read(j1), s2.read(j2);
    d1.step(i1, o1, kCycle), d2.step(i2, o2, kCycle), e1.step(j1, p1, kCycle), e2.step(j2, p2, kCycle);
    b1.write_axis(o1, q, Nanoseconds{0}, o2.error_register), b2.write_axis(o2, q, Nanoseconds{0}, o1.error_register);
    s1.write(p1, q), s2.write(p2, q);
    ASSERT_EQ(both.store.get<std::uint16_t>(0x6041, 0), alone1.store.get<std::uint16_t>(0x6041, 0)) << c;
    ASSERT_EQ(both.store.get<std::uint16_t>(0x6841, 0), alone2.store.get<std::uint16_t>(0x6041, 0)) << c;
    ASSERT_EQ(both.store.get<std::int32_t>(0x6064, 0), alone1.store.get<std::int32_t>(0x6064, 0)) << c;
    ASSERT_EQ(both.store.get<std::int32_t>(0x6864, 0), alone2.store.get<std::int32_t>(0x6064, 0)) << c;
    ASSERT_EQ(both.store.get<std::int32_t>(0x686C, 0), alone2.store.get<std::int32_t>(0x606C, 0)) << c;
  }
  // Both reached their own targets (6067h is absent here: the drive default window, 100).
  EXPECT_NEAR(both.store.get<std::int32_t>(0x6064, 0), target[0], 100);
  EXPECT_NEAR(both.store.get<std::int32_t>(0x6864, 0), target[1], 100);
  EXPECT_EQ(both.store.get<std::uint16_t>(0x6041, 0) & 0x0400, 0x0400);
  EXPECT_EQ(both.store.get<std::uint16_t>(0x6841, 0) & 0x0400, 0x0400);
}

TEST(DriveAxes, EmcyNamesItsAxisAndCarriesTheDeviceErrorRegister) {
  const od::DeviceDescription dev = servo(2);
  coe::test::Rig rig(dev);
  coe::Emergency emcy(rig.mailbox, rig.store);
  rig.mailbox.poll(Nanoseconds{0});
  DriveBinding b2(rig.store, &emcy, dev.drive->axes, 2);
  Drive drive(generic_drive(), PlantParameters{});
  DriveInputs in;
  DriveOutputs out;
  b2.read(in);
  drive.step(in, out, std::chrono::milliseconds(1));
  drive.raise_fault(FaultKind::OverTorque);  // 8311h, 1001h bit 1
  drive.step(in, out, std::chrono::milliseconds(1));
  b2.write_axis(out, drive.emergencies(), Nanoseconds{0}, 0x21);  // axis 1 has a following error
  EXPECT_EQ(rig.store.get<std::uint16_t>(0x683F, 0), 0x8311);
  EXPECT_EQ(rig.store.get<std::uint16_t>(0x603F, 0), 0);
  EXPECT_EQ(rig.store.get<std::uint8_t>(0x1001, 0), 0x23);
  rig.mailbox.poll(Nanoseconds{0});
  auto msg = rig.fetch();
  ASSERT_TRUE(msg);
  ASSERT_EQ(msg->size(), 16u);
  EXPECT_EQ((*msg)[8], 0x11);
  EXPECT_EQ((*msg)[9], 0x83);
  EXPECT_EQ((*msg)[10], 0x23);  // the device's 1001h
  EXPECT_EQ((*msg)[11], 2);     // EMCY byte 3: axis 2
  EXPECT_EQ((*msg)[12], 0);
}

}  // namespace
}  // namespace ecat::ds402
