// DriveBinding: objects copied between the CoE object store and the drive's
// plain structs, missing objects skipped, 6502h/60E3h published, and the
// drive's emergency requests sent as CoE emergency messages.
#include "ds402/od_binding.hpp"

#include <gtest/gtest.h>

#include "ds402/drive.hpp"
#include "tests/coe/rig.hpp"

namespace ecat::ds402 {
namespace {

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

od::DeviceDescription servo() {
  using T = od::DataType;
  od::DeviceDescription dev;
  auto& d = dev.dictionary;
  var(d, 0x1001, T::Unsigned8, 8);
  var(d, 0x603F, T::Unsigned16, 16);
  var(d, 0x6040, T::Unsigned16, 16);
  var(d, 0x6041, T::Unsigned16, 16);
  var(d, 0x6060, T::Integer8, 8);
  var(d, 0x6061, T::Integer8, 8);
  var(d, 0x605A, T::Integer16, 16, {0x02, 0x00});
  var(d, 0x6064, T::Integer32, 32);
  var(d, 0x6065, T::Unsigned32, 32, {0x10, 0x27, 0, 0});  // 10000
  var(d, 0x607A, T::Integer32, 32);
  array(d, 0x607D, T::Integer32, 32, 2);
  array(d, 0x6099, T::Unsigned32, 32, 2);
  var(d, 0x6098, T::Integer8, 8);
  var(d, 0x60B9, T::Unsigned16, 16);
  array(d, 0x60E3, T::Integer16, 16, 4);
  var(d, 0x60FD, T::Unsigned32, 32);
  var(d, 0x6502, T::Unsigned32, 32);
  return dev;
}

TEST(DriveBinding, CopiesObjectsBothWays) {
  coe::test::Rig rig(servo());
  DriveBinding b(rig.store);
  EXPECT_EQ(b.bound_inputs(), 10u);  // 6040, 605A, 6060, 6065, 607A, 607D:1/2, 6098, 6099:1/2
  EXPECT_EQ(b.bound_outputs(), 7u);  // 6041, 6061, 6064, 603F, 60B9, 60FD, 6502
  ASSERT_TRUE(rig.store.set<std::uint16_t>(0x6040, 0, 0x000F));
  ASSERT_TRUE(rig.store.set<std::int8_t>(0x6060, 0, 8));
  ASSERT_TRUE(rig.store.set<std::int32_t>(0x607A, 0, -123456));
  ASSERT_TRUE(rig.store.set<std::int32_t>(0x607D, 1, -1000));
  ASSERT_TRUE(rig.store.set<std::uint32_t>(0x6099, 2, 777));
  DriveInputs in;
  in.profile_velocity = 4242;  // 6081h absent: keeps its value
  b.read(in);
  EXPECT_EQ(in.controlword, 0x000F);
  EXPECT_EQ(in.modes_of_operation, 8);
  EXPECT_EQ(in.target_position, -123456);
  EXPECT_EQ(in.software_limit_min, -1000);
  EXPECT_EQ(in.homing_speed_zero, 777u);
  EXPECT_EQ(in.following_error_window, 10000u);  // the dictionary default
  EXPECT_EQ(in.profile_velocity, 4242u);

  DriveOutputs out;
  out.statusword = 0x1237;
  out.modes_of_operation_display = -3;
  out.position_actual = -99;
  out.error_code = 0x8611;
  out.error_register = 0x21;
  out.touch_probe_status = 0x0203;
  out.digital_inputs = 0x00010004;
  EmcyQueue none;
  b.write(out, none);
  EXPECT_EQ(rig.store.get<std::uint16_t>(0x6041, 0), 0x1237);
  EXPECT_EQ(rig.store.get<std::int8_t>(0x6061, 0), -3);
  EXPECT_EQ(rig.store.get<std::int32_t>(0x6064, 0), -99);
  EXPECT_EQ(rig.store.get<std::uint16_t>(0x603F, 0), 0x8611);
  EXPECT_EQ(rig.store.get<std::uint8_t>(0x1001, 0), 0x21);  // no Emergency: written directly
  EXPECT_EQ(rig.store.get<std::uint16_t>(0x60B9, 0), 0x0203);
  EXPECT_EQ(rig.store.get<std::uint32_t>(0x60FD, 0), 0x00010004u);
}

TEST(DriveBinding, PublishesModesAndHomingMethods) {
  coe::test::Rig rig(servo());
  DriveBinding b(rig.store);
  b.publish(*drive_personality("yaskawa-sigma5-sd"));
  EXPECT_EQ(rig.store.get<std::uint32_t>(0x6502, 0), 0x3EDu);
  // Yaskawa: 1, 2, 7, 8, ... only the first four fit the 4-entry array.
  EXPECT_EQ(rig.store.get<std::int16_t>(0x60E3, 1), 1);
  EXPECT_EQ(rig.store.get<std::int16_t>(0x60E3, 2), 2);
  EXPECT_EQ(rig.store.get<std::int16_t>(0x60E3, 3), 7);
  EXPECT_EQ(rig.store.get<std::int16_t>(0x60E3, 4), 8);
}

coe::WriteRequest write(std::uint16_t index, const std::vector<std::uint8_t>& bytes) {
  return coe::WriteRequest{index, 0, bytes, od::EsmState::PreOp};
}

TEST(DriveBinding, SdoWritesOutsideThePersonalityAreRefused) {
  coe::test::Rig rig(servo());
  DriveBinding b(rig.store);
  b.publish(*drive_personality("welcon"));
  const std::vector<std::uint8_t> csp{8}, ip{7}, none{0}, m1{1}, m36{36}, qs6{6, 0}, qs3{3, 0};
  EXPECT_TRUE(rig.store.write(write(0x6060, csp)));
  EXPECT_EQ(rig.store.get<std::int8_t>(0x6060, 0), 8);
  EXPECT_EQ(rig.store.write(write(0x6060, ip)).error(), coe::SdoAbort::ValueRange);  // not in 0x3AF
  EXPECT_EQ(rig.store.get<std::int8_t>(0x6060, 0), 8);
  EXPECT_TRUE(rig.store.write(write(0x6060, none)));
  EXPECT_TRUE(rig.store.write(write(0x6098, m1)));
  EXPECT_EQ(rig.store.write(write(0x6098, m36)).error(), coe::SdoAbort::ValueRange);
  EXPECT_TRUE(rig.store.write(write(0x605A, qs6)));
  EXPECT_EQ(rig.store.write(write(0x605A, qs3)).error(), coe::SdoAbort::ValueRange);  // Welcon: 3 unsupported
  EXPECT_EQ(rig.store.get<std::int16_t>(0x605A, 0), 6);
}

TEST(DriveBinding, DriveFaultBecomesACoeEmergency) {
  coe::test::Rig rig(servo());
  coe::Emergency emcy(rig.mailbox, rig.store);
  rig.mailbox.poll(Nanoseconds{0});  // open the mailbox
  DriveBinding b(rig.store, &emcy);
  Drive drive(generic_drive(), PlantParameters{});
  DriveInputs in;
  DriveOutputs out;
  b.read(in);
  drive.step(in, out, std::chrono::milliseconds(1));
  drive.raise_fault(FaultKind::FollowingError);
  drive.step(in, out, std::chrono::milliseconds(1));
  b.write(out, drive.emergencies(), Nanoseconds{0});
  EXPECT_EQ(b.emergencies_lost(), 0u);
  EXPECT_TRUE(drive.emergencies().empty());
  EXPECT_EQ(rig.store.get<std::uint16_t>(0x603F, 0), 0x8611);
  EXPECT_EQ(rig.store.get<std::uint8_t>(0x1001, 0), 0x21);
  rig.mailbox.poll(Nanoseconds{0});
  auto msg = rig.fetch();
  ASSERT_TRUE(msg);
  // Mailbox header (length 10, type CoE), CoE header service 1 (emergency),
  // error code 8611h, error register 21h, five manufacturer bytes.
  ASSERT_EQ(msg->size(), 16u);
  EXPECT_EQ((*msg)[5] & 0x0F, 0x03);
  EXPECT_EQ((*msg)[7] >> 4, 0x1);
  EXPECT_EQ((*msg)[8], 0x11);
  EXPECT_EQ((*msg)[9], 0x86);
  EXPECT_EQ((*msg)[10], 0x21);
}

}  // namespace
}  // namespace ecat::ds402
