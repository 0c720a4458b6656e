// Pre-defined error field 1003h (CiA 301 §7.5.2.3; coe::ErrorField): newest
// first, count in :00, writing 0 clears, other values refused.
#include "coe/error_field.hpp"

#include <gtest/gtest.h>

#include "coe/emergency.hpp"
#include "tests/coe/rig.hpp"

namespace ecat::coe {
namespace {

using test::Frame;

od::DeviceDescription device_with_error_field(std::size_t depth) {
  od::DeviceDescription d = test::make_device();
  // SI0 read-write (the number of errors), the entries read-only.
  od::Object o = test::composite(0x1003, "Pre-defined error field", od::ObjectCode::Array, od::DataType::Unsigned32, test::kRw, {}, 0);
  for (std::size_t k = 1; k <= depth; ++k) {
    o.entries.push_back(test::entry(static_cast<std::uint8_t>(k), "Standard error field", od::DataType::Unsigned32, 32, test::kRo, {0, 0, 0, 0}));
  }
  (void)d.dictionary.put(o);
  return d;
}

std::uint32_t field(const test::Rig& rig, std::uint8_t sub) { return rig.store.get<std::uint32_t>(0x1003, sub); }
std::uint8_t count(const test::Rig& rig) { return rig.store.get<std::uint8_t>(0x1003, 0); }

TEST(ErrorField, EmergenciesNewestFirst) {
  test::Rig rig(device_with_error_field(3));
  Emergency emcy(rig.mailbox, rig.store);
  ASSERT_TRUE(emcy.error_field().active());
  EXPECT_EQ(emcy.error_field().depth(), 3u);
  EXPECT_EQ(count(rig), 0);
  (void)emcy.raise(0x2310, 0x03, {0x34, 0x12, 0, 0, 0});
  EXPECT_EQ(count(rig), 1);
  EXPECT_EQ(field(rig, 1), 0x12342310u);  // additional information = manufacturer bytes 0-1
  (void)emcy.raise(0x0000, 0x00);         // error reset: not an error, not kept
  EXPECT_EQ(count(rig), 1);
  (void)emcy.raise(0x7500, 0x11);
  (void)emcy.raise(0x8611, 0x21);
  EXPECT_EQ(count(rig), 3);
  EXPECT_EQ(field(rig, 1), 0x00008611u);
  EXPECT_EQ(field(rig, 2), 0x00007500u);
  EXPECT_EQ(field(rig, 3), 0x12342310u);
  (void)emcy.raise(0x5530, 0x01);  // full: the oldest is lost
  EXPECT_EQ(count(rig), 3);
  EXPECT_EQ(field(rig, 1), 0x00005530u);
  EXPECT_EQ(field(rig, 3), 0x00007500u);
}

TEST(ErrorField, WriteZeroClearsOtherValuesRefused) {
  test::Rig rig(device_with_error_field(2));
  ErrorField errors(rig.store);
  ASSERT_TRUE(errors.active());
  errors.add(0x2310);
  errors.add(0x3210);
  ASSERT_EQ(count(rig), 2);
  // 1003h:00 = 1: abort 06090030h, nothing changed.
  EXPECT_EQ(rig.sdo_request(test::sdo(0x2F, 0x1003, 0, 1)), test::sdo(0x80, 0x1003, 0, 0x06090030));
  EXPECT_EQ(count(rig), 2);
  EXPECT_EQ(field(rig, 1), 0x3210u);
  // 1003h:01 is read-only.
  EXPECT_EQ(rig.sdo_request(test::sdo(0x23, 0x1003, 1, 0)), test::sdo(0x80, 0x1003, 1, 0x06010002));
  // 1003h:00 = 0 clears every entry (replies carry CoE service 3, SDO response).
  auto response = [](std::uint8_t cmd, std::uint32_t data) {
    Frame f = test::sdo(cmd, 0x1003, 0, data);
    f[1] = 0x30;
    return f;
  };
  EXPECT_EQ(rig.sdo_request(test::sdo(0x2F, 0x1003, 0, 0)), response(0x60, 0));
  EXPECT_EQ(count(rig), 0);
  EXPECT_EQ(field(rig, 1), 0u);
  EXPECT_EQ(field(rig, 2), 0u);
  EXPECT_EQ(rig.sdo_request(test::sdo(0x40, 0x1003, 0, 0)), response(0x4F, 0));
}

TEST(ErrorField, AbsentWithoutEntries) {
  test::Rig rig;  // no 1003h
  ErrorField errors(rig.store);
  EXPECT_FALSE(errors.active());
  errors.add(0x2310);  // nothing to record, no crash
  EXPECT_EQ(rig.store.slot(0x1003, 0), nullptr);
}

}  // namespace
}  // namespace ecat::coe
