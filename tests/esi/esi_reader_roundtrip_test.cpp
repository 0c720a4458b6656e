// ESI import of our own output: model -> ESI -> model -> ESI is byte-identical,
// for the test servo and for every shipped device, with no warnings.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "esi/device_loader.hpp"
#include "esi/esi_reader.hpp"
#include "esi/esi_writer.hpp"
#include "esi/sii_writer.hpp"
#include "esi_test_device.hpp"

namespace ecat::esi {
namespace {

// The first line where a and b differ, with its neighbours ("" if equal).
std::string first_difference(const std::string& a, const std::string& b) {
  std::istringstream sa(a), sb(b);
  std::vector<std::string> la, lb;
  for (std::string l; std::getline(sa, l);) la.push_back(l);
  for (std::string l; std::getline(sb, l);) lb.push_back(l);
  for (std::size_t i = 0; i < std::max(la.size(), lb.size()); ++i) {
    const std::string x = i < la.size() ? la[i] : "<end>";
    const std::string y = i < lb.size() ? lb[i] : "<end>";
    if (x != y) {
      std::string ctx;
      for (std::size_t k = i >= 6 ? i - 6 : 0; k < i; ++k) ctx += "  " + la[k] + "\n";
      return "line " + std::to_string(i + 1) + ":\n" + ctx + "- " + x + "\n+ " + y;
    }
  }
  return {};
}

void expect_stable(const od::DeviceDescription& d) {
  const std::string first = write_esi(d);
  std::vector<EsiWarning> warnings;
  auto back = read_esi_string(first, "first.xml", {}, &warnings);
  ASSERT_TRUE(back) << back.error().to_string();
  for (const auto& w : warnings) ADD_FAILURE() << w.to_string("first.xml");
  const std::string second = write_esi(*back);
  EXPECT_EQ(first_difference(first, second), "");
  // The SII made from the imported model is the same too.
  auto a = write_sii(d);
  auto b = write_sii(*back);
  ASSERT_EQ(a.has_value(), b.has_value());
  if (a) {
    EXPECT_EQ(*a, *b);
  }
}

TEST(EsiRoundTrip, TestServoIsByteIdentical) { expect_stable(test::make_test_device()); }

TEST(EsiRoundTrip, ImportedModelMatchesTheOriginal) {
  const auto d = test::make_test_device();
  auto back = read_esi_string(write_esi(d), "x.xml");
  ASSERT_TRUE(back);
  const auto& id = back->identity;
  EXPECT_EQ(id.vendor_id, 0xABCu);
  EXPECT_EQ(id.vendor_name, "Example & Co");
  EXPECT_EQ(id.product_code, 0x1234u);
  EXPECT_EQ(id.revision, 0x20001u);
  EXPECT_EQ(id.name, "Test Servo");
  EXPECT_EQ(id.type_name, "TS-100");
  EXPECT_EQ(id.group_name, "Servo drives");
  EXPECT_EQ(id.device_type, 0x00020192u);
  ASSERT_TRUE(back->drive);
  EXPECT_EQ(back->drive->supported_modes, 0x3A5u);
  EXPECT_EQ(back->esc.pdi_control, 0x0C05);
  EXPECT_EQ(back->esc.pdi_configuration, 0x4400);
  EXPECT_EQ(back->esc.eeprom_bytes, 2048);
  ASSERT_EQ(back->sync_managers.size(), 4u);
  EXPECT_EQ(back->sync_managers[1].type, od::SmType::MailboxIn);
  EXPECT_EQ(back->sync_managers[1].start_address, 0x1080);
  EXPECT_EQ(back->sync_managers[1].default_size, 128);
  EXPECT_EQ(back->sync_managers[2].control, 0x64);
  EXPECT_EQ(back->fmmus, d.fmmus);
  ASSERT_EQ(back->dc_op_modes.size(), 2u);
  EXPECT_EQ(back->dc_op_modes[1].assign_activate, 0x0300);
  EXPECT_EQ(back->dc_op_modes[1].cycle_time_sync0_factor, 1);
  EXPECT_EQ(back->dc_op_modes[0].cycle_time_sync0_factor, 1);
  ASSERT_EQ(back->tx_pdos.size(), 1u);
  EXPECT_TRUE(back->tx_pdos[0].fixed);
  EXPECT_EQ(back->tx_pdos[0].sm, 3);
  EXPECT_EQ(back->rx_pdos[0].entries[3].index, 0);
  EXPECT_EQ(back->rx_pdos[0].entries[3].bit_length, 8);
  EXPECT_EQ(back->rx_pdos[0].entries[1].type, od::DataType::Integer32);
  // Dictionary: every object, entry, type, access and value.
  ASSERT_EQ(back->dictionary.size(), d.dictionary.size());
  for (const auto& o : d.dictionary.objects()) {
    const auto* b = back->dictionary.find(o.index);
    ASSERT_NE(b, nullptr) << std::hex << o.index;
    EXPECT_EQ(b->code, o.code) << std::hex << o.index;
    EXPECT_EQ(b->name, o.name);
    ASSERT_EQ(b->entries.size(), o.entries.size()) << std::hex << o.index;
    for (std::size_t i = 0; i < o.entries.size(); ++i) {
      const auto& x = o.entries[i];
      const auto& y = b->entries[i];
      EXPECT_EQ(y.subindex, x.subindex);
      EXPECT_EQ(y.name, x.name);
      EXPECT_EQ(y.type, x.type) << std::hex << o.index << ":" << int(x.subindex);
      EXPECT_EQ(y.bit_length, x.bit_length);
      EXPECT_EQ(y.access.bits, x.access.bits) << std::hex << o.index << ":" << int(x.subindex);
      EXPECT_EQ(y.default_value, x.default_value) << std::hex << o.index << ":" << int(x.subindex);
      EXPECT_EQ(y.min_value, x.min_value);
      EXPECT_EQ(y.max_value, x.max_value);
    }
  }
}

TEST(EsiRoundTrip, ShippedDevicesAreByteIdentical) {
  const auto dir = std::filesystem::path(ECAT_SOURCE_DIR) / "xml" / "devices";
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() != ".xml") continue;
    SCOPED_TRACE(e.path().filename().string());
    auto d = load_device_file(e.path());
    ASSERT_TRUE(d) << d.error().to_string();
    expect_stable(*d);
    ++n;
  }
  EXPECT_GT(n, 0);
}

}  // namespace
}  // namespace ecat::esi
