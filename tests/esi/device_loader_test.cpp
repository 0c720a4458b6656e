// The device loader on the shipped generic servo: exact objects, values and
// layout, including the objects derived from Identity, SMs, Dc, PDOs and
// Drive (docs/device-format.md "Derived objects").
#include <gtest/gtest.h>

#include <filesystem>

#include "esi/device_loader.hpp"

namespace ecat::esi {
namespace {

using od::Access;
using od::DataType;
using od::ObjectCode;
using od::Value;

const std::string kServo = std::string(ECAT_SOURCE_DIR) + "/xml/devices/generic-servo.xml";

class GenericServo : public ::testing::Test {
 protected:
  void SetUp() override {
    auto loaded = load_device_file(kServo);
    ASSERT_TRUE(loaded.has_value()) << loaded.error().to_string();
    dev = std::move(*loaded);
  }
  const od::Entry& entry(std::uint16_t index, std::uint8_t sub) {
    const od::Entry* e = dev.dictionary.find(index, sub);
    if (e == nullptr) ADD_FAILURE() << std::hex << index << ":" << int(sub) << " missing";
    static const od::Entry kNone;
    return e ? *e : kNone;
  }
  od::DeviceDescription dev;
};

TEST_F(GenericServo, Identity) {
  EXPECT_EQ(dev.identity.vendor_id, 0u);
  EXPECT_EQ(dev.identity.product_code, 0x00000402u);
  EXPECT_EQ(dev.identity.revision, 0x00010000u);
  EXPECT_EQ(dev.identity.device_type, 0x00020192u);
  EXPECT_EQ(dev.identity.name, "Generic servo");
  EXPECT_EQ(dev.identity.type_name, "ECATSLAVE-SERVO-1");
  EXPECT_EQ(dev.identity.placeholders, (std::vector<std::string>{"vendorId", "productCode", "revision"}));
  EXPECT_EQ(dev.source_file, kServo);
}

TEST_F(GenericServo, EscMailboxAndLayout) {
  EXPECT_EQ(dev.esc.process_ram_bytes, 8192u);
  EXPECT_EQ(dev.esc.eeprom_bytes, 2048u);
  EXPECT_EQ(dev.esc.pdi_control, 0x0C05u);  // SPI, DC SYNC out + latch in units enabled
  EXPECT_TRUE(dev.mailbox.coe);
  EXPECT_FALSE(dev.mailbox.foe);
  ASSERT_EQ(dev.sync_managers.size(), 4u);
  EXPECT_EQ(dev.sync_managers[0].type, od::SmType::MailboxOut);
  EXPECT_EQ(dev.sync_managers[0].start_address, 0x1000u);
  EXPECT_EQ(dev.sync_managers[0].default_size, 128u);
  EXPECT_EQ(dev.sync_managers[0].control, 0x26u);
  EXPECT_EQ(dev.sync_managers[1].type, od::SmType::MailboxIn);
  EXPECT_EQ(dev.sync_managers[1].start_address, 0x1080u);
  EXPECT_EQ(dev.sync_managers[1].control, 0x22u);
  EXPECT_EQ(dev.sync_managers[2].type, od::SmType::Outputs);
  EXPECT_EQ(dev.sync_managers[2].start_address, 0x1100u);
  EXPECT_EQ(dev.sync_managers[2].default_size, 0u);
  EXPECT_EQ(dev.sync_managers[2].max_size, 256u);
  EXPECT_EQ(dev.sync_managers[2].control, 0x64u);
  EXPECT_EQ(dev.sync_managers[3].type, od::SmType::Inputs);
  EXPECT_EQ(dev.sync_managers[3].start_address, 0x1400u);
  EXPECT_EQ(dev.fmmus, (std::vector<od::FmmuUsage>{od::FmmuUsage::Outputs, od::FmmuUsage::Inputs,
                                                    od::FmmuUsage::MailboxState}));
  ASSERT_EQ(dev.dc_op_modes.size(), 3u);
  EXPECT_EQ(dev.dc_op_modes[0].name, "FreeRun");
  EXPECT_EQ(dev.dc_op_modes[2].name, "DC");
  EXPECT_EQ(dev.dc_op_modes[2].assign_activate, 0x0300u);
  EXPECT_EQ(dev.dc_op_modes[2].cycle_time_sync0_factor, 1);
  EXPECT_EQ(dev.sync.min_cycle_time_ns, 125000u);
  EXPECT_TRUE(dev.sync.dc_sync0);
  EXPECT_FALSE(dev.sync.dc_sync1);
}

TEST_F(GenericServo, Pdos) {
  ASSERT_EQ(dev.rx_pdos.size(), 2u);
  ASSERT_EQ(dev.tx_pdos.size(), 2u);
  const od::Pdo& rx = dev.rx_pdos[0];
  EXPECT_EQ(rx.index, 0x1600u);
  EXPECT_TRUE(rx.fixed);
  EXPECT_EQ(rx.sm, std::optional<std::uint8_t>(2));
  ASSERT_EQ(rx.entries.size(), 6u);
  EXPECT_EQ(rx.entries[1].index, 0x607Au);
  EXPECT_EQ(rx.entries[1].bit_length, 32u);
  EXPECT_EQ(rx.entries[1].name, "Target position");
  EXPECT_EQ(rx.entries[1].type, DataType::Integer32);
  EXPECT_EQ(rx.entries[5].index, 0u);  // pad
  EXPECT_EQ(rx.entries[5].bit_length, 8u);
  EXPECT_EQ(rx.bit_length(), 112u);
  EXPECT_EQ(dev.tx_pdos[0].index, 0x1A00u);
  EXPECT_EQ(dev.tx_pdos[0].bit_length(), 128u);
  EXPECT_EQ(dev.rx_pdos[1].index, 0x1601u);
  EXPECT_FALSE(dev.rx_pdos[1].fixed);
  EXPECT_FALSE(dev.rx_pdos[1].sm.has_value());
}

TEST_F(GenericServo, DerivedIdentityObjects) {
  EXPECT_EQ(entry(0x1000, 0).default_value, (Value{0x92, 0x01, 0x02, 0x00}));
  EXPECT_EQ(entry(0x1008, 0).default_value, (Value{'G', 'e', 'n', 'e', 'r', 'i', 'c', ' ', 's', 'e', 'r', 'v', 'o'}));
  EXPECT_EQ(entry(0x1008, 0).bit_length, 13u * 8);
  EXPECT_TRUE(entry(0x1008, 0).access.is_const);
  EXPECT_EQ(entry(0x1009, 0).default_value, (Value{'1', '.', '0'}));
  const od::Object* id = dev.dictionary.find(0x1018);
  ASSERT_NE(id, nullptr);
  EXPECT_EQ(id->code, ObjectCode::Record);
  EXPECT_EQ(id->type, DataType::Identity);
  ASSERT_EQ(id->entries.size(), 5u);
  EXPECT_EQ(id->entries[0].default_value, Value{4});
  EXPECT_EQ(id->entries[1].default_value, (Value{0, 0, 0, 0}));
  EXPECT_EQ(id->entries[2].default_value, (Value{0x02, 0x04, 0, 0}));
  EXPECT_EQ(id->entries[3].default_value, (Value{0, 0, 0x01, 0}));
}

TEST_F(GenericServo, DerivedSmObjects) {
  const od::Object* comm = dev.dictionary.find(0x1C00);
  ASSERT_NE(comm, nullptr);
  ASSERT_EQ(comm->entries.size(), 5u);
  EXPECT_EQ(comm->entries[0].default_value, Value{4});
  for (std::uint8_t i = 1; i <= 4; ++i) EXPECT_EQ(comm->entries[i].default_value, Value{i});

  const od::Object* assign = dev.dictionary.find(0x1C12);
  ASSERT_NE(assign, nullptr);
  EXPECT_EQ(assign->code, ObjectCode::Array);
  EXPECT_EQ(assign->type, DataType::Unsigned16);
  ASSERT_EQ(assign->entries.size(), 3u);  // sub 0 + one element per RxPDO
  EXPECT_EQ(assign->entries[0].default_value, Value{1});
  EXPECT_EQ(assign->entries[0].access.bits, Access::kReadAll | Access::kWritePreOp);
  EXPECT_EQ(assign->entries[1].default_value, (Value{0x00, 0x16}));
  EXPECT_EQ(assign->entries[2].default_value, (Value{0x00, 0x00}));
  EXPECT_EQ(entry(0x1C13, 1).default_value, (Value{0x00, 0x1A}));

  EXPECT_EQ(entry(0x1C32, 0).default_value, Value{0x20});
  EXPECT_EQ(entry(0x1C32, 4).default_value, (Value{0x07, 0x00}));  // free run, SM, DC
  EXPECT_EQ(entry(0x1C33, 5).default_value, (Value{0x48, 0xE8, 0x01, 0x00}));  // 125000 ns
}

TEST_F(GenericServo, DerivedPdoMappings) {
  const od::Object* map = dev.dictionary.find(0x1600);
  ASSERT_NE(map, nullptr);
  EXPECT_EQ(map->code, ObjectCode::Record);
  EXPECT_EQ(map->type, DataType::PdoMapping);
  EXPECT_EQ(map->name, "Outputs (CSP/CSV/CST)");
  ASSERT_EQ(map->entries.size(), 7u);
  EXPECT_EQ(map->entries[0].default_value, Value{6});
  EXPECT_EQ(map->entries[0].access.bits, Access::kRo);  // fixed
  EXPECT_EQ(map->entries[1].default_value, (Value{0x10, 0x00, 0x40, 0x60}));  // 6040:00, 16 bits
  EXPECT_EQ(map->entries[2].default_value, (Value{0x20, 0x00, 0x7A, 0x60}));
  EXPECT_EQ(map->entries[6].default_value, (Value{0x08, 0x00, 0x00, 0x00}));  // gap

  const od::Object* conf = dev.dictionary.find(0x1A01);
  ASSERT_NE(conf, nullptr);
  ASSERT_EQ(conf->entries.size(), 9u);  // maxEntries 8
  EXPECT_EQ(conf->entries[0].default_value, Value{4});
  EXPECT_EQ(conf->entries[0].access.bits, Access::kReadAll | Access::kWritePreOp);
  EXPECT_EQ(conf->entries[1].default_value, (Value{0x10, 0x00, 0xB9, 0x60}));
  EXPECT_EQ(conf->entries[8].default_value, (Value{0, 0, 0, 0}));
  EXPECT_EQ(conf->entries[8].access.bits, Access::kReadAll | Access::kWritePreOp);
}

TEST_F(GenericServo, DriveObjects) {
  ASSERT_TRUE(dev.drive.has_value());
  // PP bit 0, PV 2, PT 3, HM 5, CSP 7, CSV 8, CST 9.
  EXPECT_EQ(dev.drive->supported_modes, 0x3ADu);
  EXPECT_EQ(entry(0x6502, 0).default_value, (Value{0xAD, 0x03, 0x00, 0x00}));
  EXPECT_EQ(dev.drive->homing_methods, (std::vector<std::int8_t>{1, 2, 17, 18, 33, 34, 35, 37}));
  const od::Object* homing = dev.dictionary.find(0x60E3);
  ASSERT_NE(homing, nullptr);
  ASSERT_EQ(homing->entries.size(), 9u);
  EXPECT_EQ(homing->entries[0].default_value, Value{8});
  EXPECT_EQ(homing->entries[8].default_value, Value{37});
  ASSERT_FALSE(dev.drive->plant.empty());
  EXPECT_EQ(dev.drive->plant[0].first, "rotor_inertia");
  EXPECT_DOUBLE_EQ(dev.drive->plant[0].second, 1.2e-4);
  EXPECT_EQ(dev.drive->plant[7].first, "encoder_resolution");
  EXPECT_DOUBLE_EQ(dev.drive->plant[7].second, 1048576.0);
  const std::string vendor = "ecatslave (placeholder vendor)";
  EXPECT_EQ(entry(0x6504, 0).default_value, Value(vendor.begin(), vendor.end()));
}

TEST_F(GenericServo, ProfileObjectsWithOverrides) {
  const od::Entry& cw = entry(0x6040, 0);
  EXPECT_EQ(cw.name, "Controlword");
  EXPECT_EQ(cw.type, DataType::Unsigned16);
  EXPECT_EQ(cw.access.bits, Access::kRw | Access::kRxPdoMappable);
  const od::Entry& sw = entry(0x6041, 0);
  EXPECT_EQ(sw.access.bits, Access::kRo | Access::kTxPdoMappable);
  // cia402.xml: 6075h default 0; generic-servo.xml overrides it with 3000 mA.
  EXPECT_EQ(entry(0x6075, 0).default_value, (Value{0xB8, 0x0B, 0, 0}));
  EXPECT_EQ(entry(0x6075, 0).unit, "mA");
  EXPECT_EQ(entry(0x608F, 1).default_value, (Value{0x00, 0x00, 0x10, 0x00}));  // 1048576
  EXPECT_EQ(entry(0x608F, 1).name, "Encoder increments");
  EXPECT_EQ(entry(0x607D, 1).default_value, (Value{0x00, 0x00, 0x00, 0x80}));  // INT32 min
  EXPECT_EQ(entry(0x60C2, 2).default_value, Value{0xFD});                     // -3
  EXPECT_EQ(entry(0x60C2, 2).access.bits, Access::kReadAll | Access::kWritePreOp);
  EXPECT_EQ(entry(0x1C32, 0x20).type, DataType::Boolean);
  EXPECT_EQ(entry(0x1C32, 0x20).bit_length, 1u);
}

TEST(DeviceLoader, DefaultDeviceIsTheGenericServo) {
  auto builtin = load_default_device();
  ASSERT_TRUE(builtin.has_value()) << builtin.error().to_string();
  auto file = load_device_file(kServo);
  ASSERT_TRUE(file.has_value());
  EXPECT_EQ(builtin->source_file, "embedded:devices/generic-servo.xml");
  ASSERT_EQ(builtin->dictionary.size(), file->dictionary.size());
  for (std::size_t i = 0; i < file->dictionary.size(); ++i) {
    const auto& a = builtin->dictionary.objects()[i];
    const auto& b = file->dictionary.objects()[i];
    EXPECT_EQ(a.index, b.index);
    ASSERT_EQ(a.entries.size(), b.entries.size());
    for (std::size_t k = 0; k < a.entries.size(); ++k) {
      EXPECT_EQ(a.entries[k].default_value, b.entries[k].default_value);
    }
  }
}

TEST(DeviceLoader, MissingFileIsAnError) {
  auto dev = load_device_file("/nonexistent/dir/device.xml");
  ASSERT_FALSE(dev.has_value());
  EXPECT_EQ(dev.error().to_string(), "/nonexistent/dir/device.xml: cannot open the device file");
}

// Every shipped device whose DC OpMode activates SYNC0 (AssignActivate
// 0x0980/0x0981 bits 8/9) enables the DC SYNC out unit in SII word 0 (0x0140
// bit 10, ESC Section I p.82): without it an ESC never generates SYNC0.
TEST(ShippedDevices, SyncOutUnitEnabledWhereSync0IsActivated) {
  constexpr std::uint16_t kSyncActivate = 0x0300;
  constexpr std::uint16_t kSyncOutUnit = 0x0400;
  std::size_t dc_devices = 0;
  for (const auto& f : std::filesystem::directory_iterator(std::string(ECAT_SOURCE_DIR) + "/xml/devices")) {
    auto d = load_device_file(f.path());
    ASSERT_TRUE(d) << f.path() << ": " << d.error().to_string();
    bool sync0 = false;
    for (const auto& m : d->dc_op_modes) sync0 = sync0 || (m.assign_activate & kSyncActivate) != 0;
    if (!sync0) continue;
    ++dc_devices;
    EXPECT_NE(d->esc.pdi_control & kSyncOutUnit, 0) << f.path().filename() << ": 0x" << std::hex << d->esc.pdi_control;
  }
  EXPECT_GE(dc_devices, 5u);  // generic servo, simtach, welcon x2, yaskawa
}

}  // namespace
}  // namespace ecat::esi
