// Import of a vendor-shaped ESI (tests/data/esi/vendor-drives.xml, written for
// these tests): device selection, every modelled value, and the warnings for
// what the model cannot hold.
#include <gtest/gtest.h>

#include <string>
#include <tuple>
#include <vector>

#include "esi/esi_reader.hpp"
#include "esi/esi_writer.hpp"

namespace ecat::esi {
namespace {

const std::string kFile = std::string(ECAT_SOURCE_DIR) + "/tests/data/esi/vendor-drives.xml";

od::Value bytes(std::initializer_list<std::uint8_t> b) { return od::Value(b); }

class VendorEsi : public ::testing::Test {
 protected:
  void SetUp() override {
    auto r = read_esi(kFile, 0x1001, 0x20000, &warnings);
    ASSERT_TRUE(r) << r.error().to_string();
    d = *r;
  }
  std::vector<EsiWarning> warnings;
  od::DeviceDescription d;
};

TEST_F(VendorEsi, Identity) {
  const auto& id = d.identity;
  EXPECT_EQ(id.vendor_id, 0x00E0F00Du);
  EXPECT_EQ(id.vendor_name, "Example Drives");  // LcId 1033 preferred
  EXPECT_EQ(id.product_code, 0x1001u);
  EXPECT_EQ(id.revision, 0x20000u);
  EXPECT_EQ(id.type_name, "EXD-100");
  EXPECT_EQ(id.name, "EXD-100 servo");
  EXPECT_EQ(id.group_type, "ExDrive");
  EXPECT_EQ(id.group_name, "Example servo drives");
  EXPECT_EQ(id.device_type, 0x00020192u);
  EXPECT_EQ(id.software_version, "2.01");
  EXPECT_TRUE(d.esc.no_lrw);  // UseLrdLwr
  ASSERT_TRUE(d.drive);
  EXPECT_EQ(d.drive->supported_modes, 0x3A1u);
}

TEST_F(VendorEsi, EscLayoutMailboxDcEeprom) {
  ASSERT_EQ(d.sync_managers.size(), 4u);
  EXPECT_EQ(d.sync_managers[0].min_size, 34);
  EXPECT_EQ(d.sync_managers[0].max_size, 256);
  EXPECT_EQ(d.sync_managers[1].start_address, 0x1100);
  EXPECT_EQ(d.sync_managers[3].type, od::SmType::Inputs);
  EXPECT_EQ(d.sync_managers[3].control, 0x20);
  EXPECT_EQ(d.fmmus, (std::vector<od::FmmuUsage>{od::FmmuUsage::Outputs, od::FmmuUsage::Inputs,
                                                 od::FmmuUsage::MailboxState}));
  EXPECT_TRUE(d.mailbox.coe);
  EXPECT_TRUE(d.mailbox.foe);
  EXPECT_FALSE(d.mailbox.eoe);
  EXPECT_TRUE(d.mailbox.sdo_info);
  EXPECT_FALSE(d.mailbox.pdo_assign);
  EXPECT_TRUE(d.mailbox.pdo_config);
  EXPECT_FALSE(d.mailbox.pdo_upload);
  ASSERT_EQ(d.dc_op_modes.size(), 3u);
  const auto& m = d.dc_op_modes[2];
  EXPECT_EQ(m.name, "DC-Sync01");
  EXPECT_EQ(m.description, "DC Sync0 and Sync1");
  EXPECT_EQ(m.assign_activate, 0x0700);
  EXPECT_EQ(m.cycle_time_sync0_factor, 1);
  EXPECT_EQ(m.shift_time_sync0, 2000);
  EXPECT_EQ(m.cycle_time_sync1_factor, -1);
  EXPECT_EQ(m.shift_time_sync1, 1000);
  EXPECT_EQ(d.dc_op_modes[0].assign_activate, 0);
  EXPECT_EQ(d.esc.eeprom_bytes, 4096);
  EXPECT_EQ(d.esc.pdi_control, 0x0E08);
  EXPECT_EQ(d.esc.pdi_configuration, 0xCC00);
  EXPECT_EQ(d.esc.sync_impulse_length, 0x1388);
  EXPECT_EQ(d.esc.pdi_configuration2, 0);
  EXPECT_TRUE(d.bootstrap_supported);
}

TEST_F(VendorEsi, Pdos) {
  ASSERT_EQ(d.rx_pdos.size(), 2u);
  const auto& rx = d.rx_pdos[0];
  EXPECT_EQ(rx.index, 0x1600);
  EXPECT_EQ(rx.name, "Outputs");
  EXPECT_TRUE(rx.fixed);
  EXPECT_TRUE(rx.mandatory);
  EXPECT_EQ(rx.sm, 2);
  EXPECT_EQ(rx.excludes, (std::vector<std::uint16_t>{0x1601}));
  ASSERT_EQ(rx.entries.size(), 4u);
  EXPECT_EQ(rx.entries[1].index, 0x607A);
  EXPECT_EQ(rx.entries[1].bit_length, 32);
  EXPECT_EQ(rx.entries[1].type, od::DataType::Integer32);
  EXPECT_EQ(rx.entries[3].index, 0);
  EXPECT_EQ(rx.entries[3].bit_length, 8);
  EXPECT_FALSE(d.rx_pdos[1].sm);
  ASSERT_EQ(d.tx_pdos.size(), 1u);
  // No DataType given: taken from the dictionary.
  EXPECT_EQ(d.tx_pdos[0].entries[1].type, od::DataType::Integer32);
}

TEST_F(VendorEsi, DictionaryVarsArraysRecords) {
  EXPECT_EQ(d.dictionary.size(), 15u);  // 17 objects, 2 skipped
  const auto* name = d.dictionary.find(0x1008, 0);
  ASSERT_NE(name, nullptr);
  EXPECT_EQ(name->type, od::DataType::VisibleString);
  EXPECT_EQ(name->bit_length, 96);
  EXPECT_EQ(name->default_value, bytes({'E', 'X', 'D', '-', '1', '0', '0'}));

  const auto* ident = d.dictionary.find(0x1018);
  ASSERT_NE(ident, nullptr);
  EXPECT_EQ(ident->code, od::ObjectCode::Record);
  EXPECT_EQ(ident->type, od::DataType::Identity);
  EXPECT_EQ(ident->type_name, "DT1018");
  EXPECT_EQ(ident->find(1)->default_value, bytes({0x0D, 0xF0, 0xE0, 0x00}));

  const auto* assign = d.dictionary.find(0x1C12);
  ASSERT_NE(assign, nullptr);
  EXPECT_EQ(assign->code, od::ObjectCode::Array);
  EXPECT_EQ(assign->type, od::DataType::Unsigned16);
  ASSERT_EQ(assign->entries.size(), 3u);
  EXPECT_EQ(assign->entries[2].subindex, 2);
  EXPECT_EQ(assign->entries[2].name, "SubIndex 002");
  EXPECT_EQ(assign->entries[1].default_value, bytes({0x00, 0x16}));
  EXPECT_EQ(assign->entries[1].access.bits, od::Access::kRo | od::Access::kWritePreOp);

  const auto* map = d.dictionary.find(0x1600);
  ASSERT_NE(map, nullptr);
  EXPECT_EQ(map->code, od::ObjectCode::Record);
  EXPECT_EQ(map->type, od::DataType::PdoMapping);
  EXPECT_EQ(map->find(3)->default_value, bytes({0x08, 0x00, 0x60, 0x60}));

  const auto* mode = d.dictionary.find(0x2000, 0);  // enum: unsigned of its size
  ASSERT_NE(mode, nullptr);
  EXPECT_EQ(mode->type, od::DataType::Unsigned16);
  EXPECT_EQ(mode->default_value, bytes({0x01, 0x00}));
  EXPECT_EQ(mode->access.bits, od::Access::kRw | od::Access::kSetting);

  const auto* filter = d.dictionary.find(0x2001);
  ASSERT_NE(filter, nullptr);
  EXPECT_EQ(filter->description, "Velocity filter settings");
  ASSERT_EQ(filter->entries.size(), 3u);
  EXPECT_EQ(filter->entries[1].type, od::DataType::Bit3);
  EXPECT_EQ(filter->entries[1].default_value, bytes({0x02}));
  EXPECT_EQ(filter->entries[1].access.bits, od::Access::kRw | od::Access::kBackup);
  const auto& gain = filter->entries[2];
  EXPECT_EQ(gain.subindex, 3);
  EXPECT_EQ(gain.min_value, bytes({0x9C, 0xFF}));
  EXPECT_EQ(gain.max_value, bytes({0x64, 0x00}));
  EXPECT_EQ(gain.default_value, bytes({0xFB, 0xFF}));
  EXPECT_EQ(gain.access.bits, od::Access::kReadPreOp | od::Access::kReadSafeOp |
                                  od::Access::kWritePreOp | od::Access::kRxPdoMappable);

  const auto* mac = d.dictionary.find(0x2002, 0);
  ASSERT_NE(mac, nullptr);
  EXPECT_EQ(mac->type, od::DataType::OctetString);
  EXPECT_EQ(mac->bit_length, 48);
  EXPECT_EQ(mac->default_value, bytes({0x00, 0x12, 0x34, 0x56, 0x78}));

  const auto* status = d.dictionary.find(0x6041, 0);  // no Info: zero default
  ASSERT_NE(status, nullptr);
  EXPECT_EQ(status->default_value, bytes({0x00, 0x00}));
  EXPECT_EQ(status->access.bits, od::Access::kRo | od::Access::kTxPdoMappable);
  const auto* target = d.dictionary.find(0x607A, 0);
  EXPECT_EQ(target->min_value, bytes({0x00, 0x00, 0x00, 0x80}));
  EXPECT_EQ(d.dictionary.find(0x2003), nullptr);
  EXPECT_EQ(d.dictionary.find(0x2004), nullptr);
}

TEST_F(VendorEsi, WarningsNameElementAndLine) {
  using W = std::tuple<std::string, int, std::string>;
  std::vector<W> got;
  for (const auto& w : warnings) got.emplace_back(w.element, w.line, w.message);
  const std::vector<W> expected = {
      {"Info", 40, "not modelled; ignored"},
      {"UnitTypes", 50, "not modelled; ignored"},
      {"SubItem", 296, "object 2003h: sub item 'Matrix' of type 'DT2003ARR' not modelled; object skipped"},
      {"Object", 534, "object 2004h: unsupported data type 'DT2004'; object skipped"},
      {"InitCmd", 684, "not modelled; ignored"},
      {"CycleTimeSync1", 712, "a fixed cycle time is not modelled; only Factor is kept"},
      {"Sm", 714, "not modelled; ignored"},
      {"Category", 724, "not modelled; ignored"},
      {"ImageData16x14", 729, "not modelled; ignored"},
      {"BootStrap", 723,
       "a Bootstrap mailbox layout other than the standard mailbox's is not modelled; the "
       "standard layout is used"},
      // An empty Slots (issue 15: Slots are read, docs/esi-sii.md "Modular devices").
      {"Slots", 719, "no module is configured by the slots' defaults; the device is imported without its modules"},
      // The twin policy (docs/twins.md): the RxPdo's gap entry is in the SII, so
      // 1600h's default follows it.
      {"Object", 407,
       "1600h default (SI0 3 0x60400010 0x607a0020 0x60600008) differs from the RxPdo entries (SI0 4 "
       "0x60400010 0x607a0020 0x60600008 0x00000008); the SII's is used"},
  };
  EXPECT_EQ(got, expected);
  EXPECT_EQ(warnings[0].to_string("f.xml"), "f.xml:40: warning: Info: not modelled; ignored");
}

TEST_F(VendorEsi, ReExportIsStable) {
  const std::string once = write_esi(d);
  auto again = read_esi_string(once, "again.xml");
  ASSERT_TRUE(again);
  EXPECT_EQ(write_esi(*again), once);
}

TEST(VendorEsiSelection, FirstDeviceWithoutSelection) {
  auto d = read_esi(kFile);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->identity.revision, 0x10000u);
  EXPECT_EQ(d->identity.name, "EXD-100 servo (rev 1)");
  EXPECT_FALSE(d->drive);
  EXPECT_TRUE(d->mailbox.coe);
  EXPECT_TRUE(d->mailbox.sdo_info);
  EXPECT_FALSE(d->mailbox.complete_access);
}

// Issue 14 item 5: a selection that matches several devices is an error that
// lists them (it used to take the first); a unique one is taken.
TEST(VendorEsiSelection, AmbiguousProductCodeIsAnErrorListingTheCandidates) {
  auto d = read_esi(kFile, 0x1001);
  ASSERT_FALSE(d);
  EXPECT_EQ(d.error().to_string(),
            kFile + ":25: 3 devices match product code #x00001001; add --product-code, --revision or --type to "
                    "choose one of: EXD-100 (product code #x00001001, revision #x00010000, line 26); EXD-100 "
                    "(product code #x00001001, revision #x00020000, line 36); EXIO-8 (product code #x00001001, "
                    "revision #x00000001, line 731)");
  auto rev2 = read_esi(kFile, std::nullopt, 0x20000);
  ASSERT_TRUE(rev2);
  EXPECT_EQ(rev2->identity.name, "EXD-100 servo");
  auto rev1 = read_esi(kFile, EsiSelection{std::nullopt, 0x10000, std::string("EXD-100")});
  ASSERT_TRUE(rev1);
  EXPECT_EQ(rev1->identity.name, "EXD-100 servo (rev 1)");
}

TEST(VendorEsiSelection, DecimalProductCodeInFile) {
  auto d = read_esi(kFile, 4097, 1);
  ASSERT_TRUE(d) << d.error().to_string();
  EXPECT_EQ(d->identity.type_name, "EXIO-8");
  EXPECT_FALSE(d->mailbox.coe);  // no Mailbox element
  EXPECT_EQ(d->tx_pdos.at(0).sm, 0);
  EXPECT_EQ(d->esc.eeprom_bytes, 256);
  EXPECT_EQ(d->esc.pdi_control, 0x0004);
}

TEST(VendorEsiSelection, UnknownDeviceIsAnError) {
  auto d = read_esi(kFile, 0x1001, 0x30000);
  ASSERT_FALSE(d);
  EXPECT_EQ(d.error().to_string(),
            kFile + ":25: no device with product code #x00001001 revision #x00030000 in this file "
                    "(it has: EXD-100 (product code #x00001001, revision #x00010000, line 26); EXD-100 "
                    "(product code #x00001001, revision #x00020000, line 36); EXIO-8 (product code "
                    "#x00001001, revision #x00000001, line 731))");
}

TEST(EsiReaderErrors, BadInputGivesFileLineMessage) {
  auto a = read_esi_string("<EtherCATInfo>\n<Vendor>\n</EtherCATInfo>", "bad.xml");
  ASSERT_FALSE(a);
  EXPECT_EQ(a.error().to_string(), "bad.xml:3: XML parse error: Start-end tags mismatch");
  auto b = read_esi_string("<Device/>", "dev.xml");
  ASSERT_FALSE(b);
  EXPECT_EQ(b.error().to_string(), "dev.xml: not an ESI file: no EtherCATInfo root element");
  auto c = read_esi_string("<EtherCATInfo>\n<Descriptions><Devices/></Descriptions></EtherCATInfo>",
                           "none.xml");
  ASSERT_FALSE(c);
  // <Devices> follows <Descriptions> on line 2: the position is line:column.
  EXPECT_EQ(c.error().to_string(), "none.xml:2:15: the file describes no device");
  auto e = read_esi("/nonexistent/x.xml");
  ASSERT_FALSE(e);
  EXPECT_EQ(e.error().to_string(), "/nonexistent/x.xml: cannot open file");
  auto f = read_esi_string(
      "<EtherCATInfo><Descriptions><Devices><Device><Type/>\n<RxPdo><Index>#xZZ</Index></RxPdo>"
      "</Device></Devices></Descriptions></EtherCATInfo>",
      "pdo.xml");
  ASSERT_FALSE(f);
  EXPECT_EQ(f.error().to_string(), "pdo.xml:2: PDO index '#xZZ' is not a 16-bit number");
}

TEST(EsiReaderErrors, ParseEsiNumber) {
  EXPECT_EQ(parse_esi_number("#x1A00"), 0x1A00u);
  EXPECT_EQ(parse_esi_number("0x1A00"), 0x1A00u);
  EXPECT_EQ(parse_esi_number("6656"), 6656u);
  EXPECT_EQ(parse_esi_number("#xFFFFFFFF"), 0xFFFFFFFFu);
  EXPECT_FALSE(parse_esi_number("#x100000000"));
  EXPECT_FALSE(parse_esi_number("-1"));
  EXPECT_FALSE(parse_esi_number("12ab"));
  EXPECT_FALSE(parse_esi_number(""));
}

}  // namespace
}  // namespace ecat::esi
