// Every shipped device in xml/devices/ (and the embedded default) gives a
// schema-valid ESI and an SII that fits its EEPROM and parses back.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>
#include <vector>

#include "esi/device_loader.hpp"
#include "esi/esi_writer.hpp"
#include "esi/sii_parser.hpp"
#include "esi/sii_writer.hpp"
#include "esi_xmllint.hpp"

namespace ecat::esi {
namespace {

std::vector<std::string> shipped_devices() {
  std::vector<std::string> out;
  const auto dir = std::filesystem::path(ECAT_SOURCE_DIR) / "xml" / "devices";
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() == ".xml") out.push_back(e.path().filename().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

class EsiShippedDevice : public ::testing::TestWithParam<std::string> {};

TEST_P(EsiShippedDevice, GivesSchemaValidEsiAndSii) {
  const auto path = std::filesystem::path(ECAT_SOURCE_DIR) / "xml" / "devices" / GetParam();
  auto device = load_device_file(path);
  ASSERT_TRUE(device) << device.error().to_string();
  const std::string xml = write_esi(*device);
  EXPECT_EQ(xml, write_esi(*device));  // deterministic
  auto sii = write_sii_detailed(*device);
  ASSERT_TRUE(sii) << sii.error();
  auto parsed = parse_sii(sii->bytes);
  ASSERT_TRUE(parsed) << parsed.error();
  EXPECT_EQ(*parsed, sii_from_device(*device, sii->detail));
  EXPECT_EQ(sii->bytes.size(), device->esc.eeprom_bytes);
  if (!test::can_validate_esi()) GTEST_SKIP() << test::why_no_esi_schema();
  const auto file = test::write_test_file("esi_" + GetParam(), xml);
  for (const auto& schema : test::esi_schemas()) {
    bool ok = false;
    const std::string out = test::xmllint_schema(file, schema, ok);
    EXPECT_TRUE(ok) << schema << ":\n" << out;
  }
}

INSTANTIATE_TEST_SUITE_P(XmlDevices, EsiShippedDevice, ::testing::ValuesIn(shipped_devices()),
                         [](const auto& param_info) {
                           const std::string& file = param_info.param;
                           std::string n = file.substr(0, file.size() - 4);
                           std::replace_if(n.begin(), n.end(),
                                           [](char c) { return !std::isalnum(static_cast<unsigned char>(c)); },
                                           '_');
                           return n;
                         });

TEST(EsiEmbeddedDefault, GivesSchemaValidEsi) {
  auto device = load_default_device();
  ASSERT_TRUE(device) << device.error().to_string();
  ASSERT_TRUE(write_sii(*device));
  if (!test::can_validate_esi()) GTEST_SKIP() << test::why_no_esi_schema();
  bool ok = false;
  const auto file = test::write_test_file("esi_default_device.xml", write_esi(*device));
  for (const auto& schema : test::esi_schemas()) {
    const std::string out = test::xmllint_schema(file, schema, ok);
    EXPECT_TRUE(ok) << schema << ":\n" << out;
  }
}

}  // namespace
}  // namespace ecat::esi
