// Real SII images through the capture's SII-only path (issue 32 item 3):
// the EEPROM dumps of an EK1100 coupler, an EL2828 digital output terminal
// and a Kollmorgen AKD drive published in ethercrab's repository
// (tests/data/sii-dumps/README.md). Identity, names and PDO counts as the
// images hold them (decoded by hand from the bytes), notes for what a
// capture of the SII alone cannot know, and the device file that reloads.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>

#include "esi/capture_model.hpp"
#include "esi/device_loader.hpp"
#include "esi/esi_writer_device_xml.hpp"

namespace ecat::esi {
namespace {

std::vector<std::uint8_t> dump(const std::string& name) {
  std::string path = ECAT_SOURCE_DIR;
  path += "/tests/data/sii-dumps/";
  path += name;
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

bool has_note(const std::vector<std::string>& notes, const std::string& part) {
  return std::any_of(notes.begin(), notes.end(), [&](const std::string& n) { return n.find(part) != std::string::npos; });
}

CaptureResult convert(const std::string& name) {
  CaptureInput in;
  in.sii = dump(name);
  EXPECT_EQ(in.sii.size(), 2048u) << name;
  auto r = device_from_capture(in);
  EXPECT_TRUE(r) << name << ": " << (r ? "" : r.error());
  return r ? std::move(*r) : CaptureResult{};
}

void expect_reloads(const od::DeviceDescription& d, const std::string& name) {
  const std::string xml = write_device_xml(d);
  auto back = load_device_string(xml, name + ".xml");
  ASSERT_TRUE(back) << name << ": " << back.error().to_string();
  // From the first load on a fixed point (the loader adds 1000h/1008h/1018h).
  const std::string second = write_device_xml(*back);
  auto again = load_device_string(second, name + ".xml");
  ASSERT_TRUE(again) << name << ": " << again.error().to_string();
  EXPECT_EQ(write_device_xml(*again), second) << name;
}

TEST(CaptureDumps, Ek1100) {
  const CaptureResult r = convert("ek1100.bin");
  const od::DeviceDescription& d = r.device;
  EXPECT_EQ(d.identity.vendor_id, 0x00000002u);
  EXPECT_EQ(d.identity.product_code, 0x044C2C52u);
  EXPECT_EQ(d.identity.revision, 0x00120000u);
  EXPECT_EQ(d.identity.type_name, "EK1100");
  EXPECT_EQ(d.identity.group_type, "SystemBk");
  EXPECT_EQ(d.identity.name, "EK1100 EtherCAT-Koppler (2A E-Bus)");
  EXPECT_EQ(d.esc.eeprom_bytes, 2048);
  EXPECT_FALSE(d.mailbox.coe);
  EXPECT_TRUE(d.rx_pdos.empty());
  EXPECT_TRUE(d.tx_pdos.empty());
  EXPECT_TRUE(d.sync_managers.empty());
  EXPECT_EQ(d.dictionary.size(), 0u);
  EXPECT_TRUE(has_note(r.notes, "SII: no SYNCM category"));
  expect_reloads(d, "ek1100");
}

TEST(CaptureDumps, El2828) {
  const CaptureResult r = convert("el2828.bin");
  const od::DeviceDescription& d = r.device;
  EXPECT_EQ(d.identity.vendor_id, 0x00000002u);
  EXPECT_EQ(d.identity.product_code, 0x0B0C3052u);
  EXPECT_EQ(d.identity.revision, 0x00110000u);
  EXPECT_EQ(d.identity.type_name, "EL2828");
  EXPECT_EQ(d.identity.name, "EL2828 8K. Dig. Ausgang 24V, 2A");
  EXPECT_FALSE(d.mailbox.coe);
  ASSERT_EQ(d.sync_managers.size(), 1u);
  EXPECT_EQ(d.sync_managers[0].start_address, 0x0F00);
  EXPECT_EQ(d.sync_managers[0].type, od::SmType::Outputs);
  ASSERT_EQ(d.rx_pdos.size(), 8u);
  EXPECT_TRUE(d.tx_pdos.empty());
  for (std::size_t k = 0; k < 8; ++k) {
    const od::Pdo& p = d.rx_pdos[k];
    EXPECT_EQ(p.index, 0x1600 + k);
    ASSERT_EQ(p.entries.size(), 1u);
    EXPECT_EQ(p.entries[0].index, 0x7000 + 0x10 * k);
    EXPECT_EQ(p.entries[0].subindex, 1);
    EXPECT_EQ(p.entries[0].bit_length, 1);
    EXPECT_EQ(p.sm, std::optional<std::uint8_t>(0));
  }
  EXPECT_EQ(d.dictionary.size(), 8u);  // 7000h..7070h, created as process data
  EXPECT_TRUE(has_note(r.notes, "PDO 1600h: 7000h:01 has no dictionary object; created as process data (1 bits)"));
  expect_reloads(d, "el2828");
}

TEST(CaptureDumps, KollmorgenAkd) {
  const CaptureResult r = convert("akd.bin");
  const od::DeviceDescription& d = r.device;
  EXPECT_EQ(d.identity.vendor_id, 0x0000006Au);
  EXPECT_EQ(d.identity.product_code, 0x00414B44u);
  EXPECT_EQ(d.identity.revision, 0x00000002u);
  EXPECT_EQ(d.identity.type_name, "AKD");
  EXPECT_EQ(d.identity.name, "AKD EtherCAT Drive (CoE)");
  EXPECT_TRUE(d.mailbox.coe);
  EXPECT_FALSE(d.mailbox.sdo_info);  // CoE details 0Dh: SDO, PDO assign, PDO config
  ASSERT_EQ(d.sync_managers.size(), 4u);
  EXPECT_EQ(d.sync_managers[0].start_address, 0x1800);
  EXPECT_EQ(d.sync_managers[0].default_size, 1024);
  EXPECT_EQ(d.tx_pdos.size(), 12u);
  EXPECT_EQ(d.rx_pdos.size(), 12u);
  // Only 1701h and 1B01h are assigned by default (SM2/SM3); the others have SM FFh.
  for (const auto* list : {&d.rx_pdos, &d.tx_pdos}) {
    for (const od::Pdo& p : *list) {
      EXPECT_EQ(p.sm.has_value(), p.index == 0x1701 || p.index == 0x1B01) << std::hex << p.index;
    }
  }
  EXPECT_TRUE(has_note(r.notes, "dictionary: not read over SDO information"));
  EXPECT_EQ(d.dc_op_modes.size(), 2u);
  expect_reloads(d, "akd");
}

}  // namespace
}  // namespace ecat::esi
