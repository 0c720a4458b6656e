// Device-format writer: ESI -> model -> device XML -> model -> ESI is stable.
// For the shipped devices (whose models already hold every derived object)
// the ESI comes back byte-identical; for an imported vendor ESI the first
// pass adds what the loader derives and the result is then a fixed point.
#include <gtest/gtest.h>

#include <filesystem>

#include "esi/device_loader.hpp"
#include "esi/esi_reader.hpp"
#include "esi/esi_writer.hpp"
#include "esi/esi_writer_device_xml.hpp"
#include "esi_test_device.hpp"
#include "esi_xmllint.hpp"

namespace ecat::esi {
namespace {

// ESI text -> model -> device XML -> model -> ESI text.
std::string through_device_xml(const std::string& esi, const std::string& label) {
  auto imported = read_esi_string(esi, label + ".esi.xml");
  EXPECT_TRUE(imported) << imported.error().to_string();
  if (!imported) return {};
  const std::string xml = write_device_xml(*imported);
  const auto path = test::write_test_file(label + ".device.xml", xml);
  auto loaded = load_device_string(xml, path);
  EXPECT_TRUE(loaded) << loaded.error().to_string();
  if (!loaded) return {};
  if (test::have_xmllint()) {
    bool ok = false;
    const std::string out =
        test::xmllint_schema(path, std::string(ECAT_SOURCE_DIR) + "/xml/schema/device.xsd", ok);
    EXPECT_TRUE(ok) << out;
  }
  return write_esi(*loaded);
}

TEST(EsiDeviceXml, ShippedDevicesComeBackByteIdentical) {
  const auto dir = std::filesystem::path(ECAT_SOURCE_DIR) / "xml" / "devices";
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() != ".xml") continue;
    SCOPED_TRACE(e.path().filename().string());
    auto d = load_device_file(e.path());
    ASSERT_TRUE(d) << d.error().to_string();
    const std::string esi = write_esi(*d);
    EXPECT_TRUE(esi == through_device_xml(esi, "devxml_" + e.path().stem().string()));
  }
}

TEST(EsiDeviceXml, TestServoReachesAFixedPoint) {
  const std::string once = through_device_xml(write_esi(test::make_test_device()), "devxml_servo1");
  ASSERT_FALSE(once.empty());
  EXPECT_TRUE(once == through_device_xml(once, "devxml_servo2"));
}

// One vendor-shaped file here; every device of every ESI in tests/data, with
// the ESI writer and schema validation, is tests/esi/twin_judge_corpus_test.cpp
// (issue 32, esi/twin_judge.hpp).
TEST(EsiDeviceXml, VendorEsiReachesAFixedPoint) {
  auto d = read_esi(std::string(ECAT_SOURCE_DIR) + "/tests/data/esi/vendor-drives.xml", 0x1001,
                    0x20000);
  ASSERT_TRUE(d);
  const std::string once = through_device_xml(write_esi(*d), "devxml_vendor1");
  ASSERT_FALSE(once.empty());
  EXPECT_TRUE(once == through_device_xml(once, "devxml_vendor2"));
}

TEST(EsiDeviceXml, WritesTheFormatsSpellings) {
  const std::string xml = write_device_xml(test::make_test_device());
  EXPECT_NE(xml.find("<Device formatVersion=\"1\">"), std::string::npos);
  EXPECT_NE(xml.find("<Object index=\"#x6502\" name=\"Supported drive modes\" type=\"UNSIGNED32\" "
                     "access=\"rw\" writeIn=\"PreOp SafeOp\" default=\"#x000003A5\" />"),
            std::string::npos);
  EXPECT_NE(xml.find("<Entry sub=\"2\" name=\"Gain\" type=\"INTEGER16\" access=\"rw\" backup=\"true\" "
                     "default=\"#xFF9C\" min=\"#xFC18\" max=\"#x03E8\" />"),
            std::string::npos);
  EXPECT_NE(xml.find("name=\"Filter\" type=\"REAL32\" access=\"rw\" default=\"1\""), std::string::npos);
  EXPECT_NE(xml.find("<Drive modes=\"PP PV HM CSP CSV CST\" />"), std::string::npos);
}

}  // namespace
}  // namespace ecat::esi
