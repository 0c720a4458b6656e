// A slave's synchronisation parts over the fake PDI: 1C32h/1C33h/10F1h in an
// ObjectStore, the ESM and the SyncController, with helpers that play the
// master (SM and DC registers, SYNC events, new output buffers).
#pragma once

#include <gtest/gtest.h>

#include <memory>

#include "../esc/esm_fixture.hpp"
#include "coe/object_store.hpp"
#include "coe/sync_controller.hpp"
#include "esc/dc/dc_registers.hpp"

namespace ecat::coe::test {

using esc::test::FakePdi;

inline od::Entry sync_entry(std::uint8_t sub, od::DataType type, std::uint16_t bits, std::uint16_t access,
                            std::uint64_t def = 0) {
  od::Entry e;
  e.subindex = sub;
  e.name = "sub" + std::to_string(sub);
  e.type = type;
  e.bit_length = bits;
  e.access.bits = access;
  e.default_value.resize((bits + 7) / 8);
  for (std::size_t i = 0; i < e.default_value.size(); ++i) e.default_value[i] = static_cast<std::uint8_t>(def >> (8 * i));
  return e;
}

// 1C32h/1C33h as the CiA 301 profile declares them (xml/profiles/cia301.xml).
inline od::Object sync_object(std::uint16_t index) {
  using od::Access;
  using od::DataType;
  od::Object o;
  o.index = index;
  o.name = index == kSmOutputParameter ? "SM output parameter" : "SM input parameter";
  o.code = od::ObjectCode::Record;
  o.type = DataType::SmSynchronisation;
  o.entries = {sync_entry(0, DataType::Unsigned8, 8, Access::kRo, 0x20),
               sync_entry(1, DataType::Unsigned16, 16, Access::kRw),
               sync_entry(2, DataType::Unsigned32, 32, Access::kRw),
               sync_entry(3, DataType::Unsigned32, 32, Access::kRo),
               sync_entry(4, DataType::Unsigned16, 16, Access::kRo),
               sync_entry(5, DataType::Unsigned32, 32, Access::kRo),
               sync_entry(6, DataType::Unsigned32, 32, Access::kRo),
               sync_entry(7, DataType::Unsigned32, 32, Access::kRo),
               sync_entry(8, DataType::Unsigned16, 16, Access::kRw),
               sync_entry(9, DataType::Unsigned32, 32, Access::kRo),
               sync_entry(0x0B, DataType::Unsigned16, 16, Access::kRo),
               sync_entry(0x0C, DataType::Unsigned16, 16, Access::kRo),
               sync_entry(0x0D, DataType::Unsigned16, 16, Access::kRo),
               sync_entry(0x20, DataType::Boolean, 1, Access::kRo)};
  return o;
}

inline od::Dictionary sync_dictionary() {
  od::Dictionary d;
  od::Object errors;
  errors.index = kErrorSettings;
  errors.name = "Error settings";
  errors.code = od::ObjectCode::Record;
  errors.type = od::DataType::Record;
  errors.entries = {sync_entry(0, od::DataType::Unsigned8, 8, od::Access::kRo, 2),
                    sync_entry(1, od::DataType::Unsigned32, 32, od::Access::kRw),
                    sync_entry(2, od::DataType::Unsigned16, 16, od::Access::kRw, 4)};
  EXPECT_TRUE(d.put(errors).has_value());
  EXPECT_TRUE(d.put(sync_object(kSmOutputParameter)).has_value());
  EXPECT_TRUE(d.put(sync_object(kSmInputParameter)).has_value());
  return d;
}

inline od::SyncLimits sync_limits() {
  od::SyncLimits l;
  l.min_cycle_time_ns = 250'000;
  l.free_run = l.sm_synchronous = l.dc_sync0 = l.dc_sync1 = true;
  return l;
}

inline constexpr std::uint16_t dc(std::uint16_t offset) { return static_cast<std::uint16_t>(0x0900 + offset); }
inline constexpr std::uint16_t kSm2Status = 0x0815;

class SyncTest : public ::testing::Test {
 protected:
  SyncTest()
      : dictionary(sync_dictionary()),
        store(dictionary),
        esm(pdi, esc::test::test_esm_config()),
        sync(pdi, store, sync_limits(), true, true) {
    sync.install();
    sync.attach(esm);
    pdi.watchdog_expired(false);
    pdi.poke_u8(kSm2Status, 0x30);  // no buffer written yet
    esm.reset();
  }

  Expected<void, SdoAbort> sdo_write(std::uint16_t index, std::uint8_t sub, std::uint32_t value, std::size_t size) {
    std::array<std::uint8_t, 4> b{};
    store_le(b.data(), value);
    return store.write({index, sub, ConstBytes(b.data(), size), od::EsmState::PreOp});
  }
  void request(std::uint16_t control) {
    pdi.master_al_control(control);
    esm.poll();
  }
  std::uint16_t status() const { return pdi.u16(esc::reg::kAlStatus); }
  std::uint16_t code() const { return pdi.u16(esc::reg::kAlStatusCode); }
  void go_preop() {
    pdi.master_sm(0, esc::test::kMbxOutStart, esc::test::kMbxLength, esc::test::kMbxOutControl, true);
    pdi.master_sm(1, esc::test::kMbxInStart, esc::test::kMbxLength, esc::test::kMbxInControl, true);
    pdi.master_sm(2, esc::test::kOutStart, 4, esc::test::kOutControl, true);
    pdi.master_sm(3, esc::test::kInStart, 6, esc::test::kInControl, true);
    pdi.poke_u8(kSm2Status, 0x30);
    request(0x0002);
    ASSERT_EQ(status(), 0x0002);
  }
  void dc_registers(std::uint8_t activation, std::uint32_t cycle0, std::uint32_t cycle1 = 0) {
    pdi.poke_u8(dc(esc::dcreg::kActivation), activation);
    pdi.poke_u32(dc(esc::dcreg::kSync0CycleTime), cycle0);
    pdi.poke_u32(dc(esc::dcreg::kSync1CycleTime), cycle1);
  }
  // One SYNC0 pulse seen by the application at t.
  SyncPoll sync0(Nanoseconds at) {
    pdi.raise_event(esc::dcreg::kAlEventSync0);
    return sync.poll(at);
  }
  // The master wrote a new SM2 buffer.
  void new_outputs() {
    buffer_ = static_cast<std::uint8_t>((buffer_ + 1) % 3);
    pdi.poke_u8(kSm2Status, static_cast<std::uint8_t>(buffer_ << 4));
  }
  void go_dc_op() {
    go_preop();
    ASSERT_TRUE(sdo_write(kSmOutputParameter, 1, 2, 2).has_value());
    ASSERT_TRUE(sdo_write(kSmInputParameter, 1, 2, 2).has_value());
    dc_registers(0x03, 1'000'000);
    request(0x0004);
    ASSERT_EQ(status(), 0x0004);
    for (int k = 0; k < 2; ++k) sync0(t += kCycle);
    new_outputs();
    request(0x0008);
    ASSERT_EQ(status(), 0x0008);
  }

  static constexpr Nanoseconds kCycle{1'000'000};
  FakePdi pdi;
  od::Dictionary dictionary;
  ObjectStore store;
  esc::Esm esm;
  SyncController sync;
  Nanoseconds t{0};
  std::uint8_t buffer_ = 0;
};

}  // namespace ecat::coe::test
