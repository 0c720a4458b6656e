// DriveBinding: objects copied between the CoE object store and the drive's
// plain structs, missing objects skipped, 6502h/60E3h published, and the
// drive's emergency requests sent as CoE emergency messages.
#include "ds402/od_binding.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <new>
#include <random>

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

// The RxPDO entries a test maps: 6040h, 607Ah, 6060h (as the generic servo's
// 1600h), laid out as ProcessDataImage would.
std::vector<coe::PdoItem> rx_pdo(coe::ObjectStore& store) {
  return {{0, 0, 16, store.slot(0x6040, 0)}, {2, 0, 32, store.slot(0x607A, 0)}, {6, 0, 8, store.slot(0x6060, 0)}};
}

// What the RxPDO copy does: the value bytes through storage(), not counted
// in the store's generation.
void pdo_write(coe::ObjectStore& store, std::uint16_t index, std::uint8_t sub, std::uint32_t v) {
  coe::ObjectStore::Slot* s = store.slot(index, sub);
  ASSERT_NE(s, nullptr);
  auto bytes = store.storage(*s);
  for (std::size_t i = 0; i < bytes.size() && i < 4; ++i) bytes[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

TEST(DriveBinding, ReadCycleCopiesMappedEntriesAndTheRestAfterStoreWrites) {
  coe::test::Rig rig(servo());
  DriveBinding b(rig.store);
  const auto items = rx_pdo(rig.store);
  DriveInputs in;
  ASSERT_TRUE(rig.store.set<std::int32_t>(0x6065, 0, 500));
  b.read_cycle(in, items);  // first call: every entry
  EXPECT_EQ(in.following_error_window, 500u);
  // Mapped entries follow the PDO copy every cycle; an unmapped entry
  // written behind the store's back (storage()) is not looked at - which
  // shows the cycle copies the mapped ones only.
  pdo_write(rig.store, 0x6040, 0, 0x000F);
  pdo_write(rig.store, 0x607A, 0, 0xFFFFFF85);  // -123
  pdo_write(rig.store, 0x6060, 0, 8);
  pdo_write(rig.store, 0x6065, 0, 777);
  b.read_cycle(in, items);
  EXPECT_EQ(in.controlword, 0x000F);
  EXPECT_EQ(in.target_position, -123);
  EXPECT_EQ(in.modes_of_operation, 8);
  EXPECT_EQ(in.following_error_window, 500u);
  // The binding's own output writes (and 1001h) do not count as a change...
  DriveOutputs out;
  out.statusword = 0x0237;
  out.error_register = 0x01;
  EmcyQueue none;
  b.write(out, none);
  b.read_cycle(in, items);
  EXPECT_EQ(in.following_error_window, 500u);
  // ... an SDO download does: every entry is copied again.
  const std::vector<std::uint8_t> window{0x10, 0x00, 0x00, 0x00};
  ASSERT_TRUE(rig.store.write(coe::WriteRequest{0x6065, 0, window, od::EsmState::Op}));
  b.read_cycle(in, items);
  EXPECT_EQ(in.following_error_window, 16u);
  // So do set(), assign() and reset_to_defaults().
  ASSERT_TRUE(rig.store.set<std::int16_t>(0x605A, 0, 6));
  b.read_cycle(in, items);
  EXPECT_EQ(in.quick_stop_option, 6);
  const std::uint8_t limit[] = {0x18, 0xFC, 0xFF, 0xFF};  // -1000
  ASSERT_TRUE(rig.store.assign(0x607D, 1, limit));
  b.read_cycle(in, items);
  EXPECT_EQ(in.software_limit_min, -1000);
  rig.store.reset_to_defaults();
  b.read_cycle(in, items);
  EXPECT_EQ(in.following_error_window, 10000u);
  EXPECT_EQ(in.quick_stop_option, 2);
  // Another RxPDO table (a new mapping): every entry, then its entries.
  pdo_write(rig.store, 0x6065, 0, 99);
  const std::vector<coe::PdoItem> other{{0, 0, 32, rig.store.slot(0x6065, 0)}};
  b.read_cycle(in, other);
  EXPECT_EQ(in.following_error_window, 99u);
  pdo_write(rig.store, 0x6065, 0, 98);
  pdo_write(rig.store, 0x6040, 0, 0x0006);
  b.read_cycle(in, other);
  EXPECT_EQ(in.following_error_window, 98u);
  EXPECT_EQ(in.controlword, 0);  // the default since the reset: no longer mapped, 6 not seen
  // invalidate(): the caller changed `in`, the next cycle copies everything.
  in.controlword = 0x1234;
  b.invalidate();
  b.read_cycle(in, other);
  EXPECT_EQ(in.controlword, 0x0006);
}

// Entries of another width than their DriveInputs/DriveOutputs field go
// through the store's typed access, mapped or not, every cycle: 6040h and
// 6041h declared UNSIGNED32 here (the fields are 16 bits), 6064h INTEGER16
// (the field is 32). Absent entries leave their fields alone.
TEST(DriveBinding, EntriesOfAnotherWidthAreConverted) {
  using T = od::DataType;
  struct Var {
    std::uint16_t index;
    od::DataType type;
    std::uint16_t bits;
  };
  od::DeviceDescription dev;
  for (const Var& v : {Var{0x6040, T::Unsigned32, 32}, Var{0x6041, T::Unsigned32, 32}, Var{0x6064, T::Integer16, 16},
                       Var{0x607A, T::Integer32, 32}}) {
    var(dev.dictionary, v.index, v.type, v.bits);
  }
  coe::test::Rig rig(std::move(dev));
  DriveBinding b(rig.store);
  EXPECT_EQ(b.bound_inputs(), 2u);
  EXPECT_EQ(b.bound_outputs(), 2u);
  const std::vector<coe::PdoItem> items{{0, 0, 32, rig.store.slot(0x6040, 0)}, {4, 0, 32, rig.store.slot(0x607A, 0)}};
  DriveInputs in;
  in.profile_velocity = 4242;
  b.read_cycle(in, items);  // every entry
  for (std::uint32_t v : {0x0001000Fu, 0x00000006u, 0xFFFF0007u}) {
    pdo_write(rig.store, 0x6040, 0, v);
    pdo_write(rig.store, 0x607A, 0, v);
    b.read_cycle(in, items);  // the mapped ones only
    EXPECT_EQ(in.controlword, static_cast<std::uint16_t>(v));
    EXPECT_EQ(in.target_position, static_cast<std::int32_t>(v));
    EXPECT_EQ(in.profile_velocity, 4242u);
  }
  DriveOutputs out;
  out.statusword = 0x1237;
  out.position_actual = -2;
  EmcyQueue none;
  b.write(out, none);
  const auto bytes = [&](std::uint16_t index) {
    const auto v = rig.store.value(index, 0);
    return std::vector<std::uint8_t>(v.begin(), v.end());
  };
  EXPECT_EQ(bytes(0x6041), (std::vector<std::uint8_t>{0x37, 0x12, 0x00, 0x00}));
  EXPECT_EQ(bytes(0x6064), (std::vector<std::uint8_t>{0xFE, 0xFF}));
  // The outputs' conversions count as store writes, yet not as new inputs.
  pdo_write(rig.store, 0x6040, 0, 0x0000001F);
  b.read_cycle(in, items);
  EXPECT_EQ(in.controlword, 0x001F);
}

// Random store writes of every kind between cycles: read_cycle() always
// leaves the inputs equal to a full read().
TEST(DriveBinding, ReadCycleEqualsFullRead) {
  coe::test::Rig rig(servo());
  DriveBinding b(rig.store);
  const auto items = rx_pdo(rig.store);
  std::mt19937 rng(7);
  auto pick = [&](std::uint32_t hi) { return std::uniform_int_distribution<std::uint32_t>(0, hi)(rng); };
  const std::pair<std::uint16_t, std::uint8_t> kEntries[] = {{0x6040, 0}, {0x6060, 0}, {0x607A, 0}, {0x605A, 0},
                                                             {0x6065, 0}, {0x607D, 1}, {0x607D, 2}, {0x6098, 0},
                                                             {0x6099, 1}, {0x6099, 2}};
  // Padding zeroed before the members get their defaults, so two inputs
  // compare with memcmp.
  alignas(DriveInputs) unsigned char cyc_bytes[sizeof(DriveInputs)] = {};
  alignas(DriveInputs) unsigned char full_bytes[sizeof(DriveInputs)] = {};
  DriveInputs& cyc = *new (cyc_bytes) DriveInputs;
  DriveOutputs out;
  EmcyQueue none;
  for (int step = 0; step < 2000; ++step) {
    SCOPED_TRACE(step);
    const auto [index, sub] = kEntries[pick(std::size(kEntries) - 1)];
    const std::uint32_t v = pick(0xFFFFFFFF);
    switch (pick(4)) {
      case 0:  // the PDO copy, mapped entries only
        if (index == 0x6040 || index == 0x6060 || index == 0x607A) pdo_write(rig.store, index, sub, v);
        break;
      case 1: ASSERT_TRUE(rig.store.set<std::uint32_t>(index, sub, v)); break;
      case 2: {
        const coe::ObjectStore::Slot* s = rig.store.slot(index, sub);
        std::vector<std::uint8_t> bytes(s->capacity);
        for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<std::uint8_t>(v >> (8 * (i % 4)));
        ASSERT_TRUE(rig.store.assign(index, sub, bytes));
        break;
      }
      case 3:
        out.statusword = static_cast<std::uint16_t>(v);
        out.position_actual = static_cast<std::int32_t>(v);
        b.write(out, none);
        break;
      default: break;
    }
    b.read_cycle(cyc, items);
    std::memset(full_bytes, 0, sizeof full_bytes);
    DriveInputs& full = *new (full_bytes) DriveInputs;
    b.read(full);
    ASSERT_EQ(0, std::memcmp(&cyc, &full, sizeof(DriveInputs)));
  }
}

}  // namespace
}  // namespace ecat::ds402
