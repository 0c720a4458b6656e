// Every device and profile shipped in xml/ loads and validates against
// xml/schema/device.xsd, with the loader and with xmllint. Parameterised over
// the folders, so device files added later are covered automatically.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "esi/device_loader.hpp"

namespace ecat::esi {
namespace {

namespace fs = std::filesystem;

const fs::path kXml = fs::path(ECAT_SOURCE_DIR) / "xml";

std::vector<std::string> xml_files(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_regular_file() && e.path().extension() == ".xml") out.push_back(e.path().filename().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string n = info.param;
  std::replace_if(n.begin(), n.end(), [](char c) { return !std::isalnum(static_cast<unsigned char>(c)); }, '_');
  return n;
}

class ShippedDevice : public ::testing::TestWithParam<std::string> {};

TEST_P(ShippedDevice, Loads) {
  auto dev = load_device_file(kXml / "devices" / GetParam());
  ASSERT_TRUE(dev.has_value()) << dev.error().to_string();
  EXPECT_FALSE(dev->dictionary.empty());
  EXPECT_NE(dev->dictionary.find(0x1018), nullptr);
  EXPECT_NE(dev->dictionary.find(0x1000), nullptr);
  EXPECT_FALSE(dev->identity.name.empty());
}

INSTANTIATE_TEST_SUITE_P(XmlDevices, ShippedDevice, ::testing::ValuesIn(xml_files(kXml / "devices")), test_name);

TEST(ShippedDevices, GenericServoIsAmongThem) {
  const auto files = xml_files(kXml / "devices");
  EXPECT_NE(std::find(files.begin(), files.end(), "generic-servo.xml"), files.end());
}

TEST(ShippedDevices, DocumentationExampleLoads) {
  std::ifstream in(fs::path(ECAT_SOURCE_DIR) / "docs" / "device-format.md");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string doc = ss.str();
  const std::string open = "```xml\n";
  const auto begin = doc.find(open);
  ASSERT_NE(begin, std::string::npos);
  const auto end = doc.find("```", begin + open.size());
  ASSERT_NE(end, std::string::npos);
  const std::string xml = doc.substr(begin + open.size(), end - begin - open.size());
  auto dev = load_device_string(xml, (kXml / "devices" / "doc-example.xml").string());
  ASSERT_TRUE(dev.has_value()) << dev.error().to_string();
  EXPECT_EQ(dev->identity.name, "Tiny drive");
  ASSERT_NE(dev->dictionary.find(0x2000, 0), nullptr);
  EXPECT_EQ(dev->dictionary.find(0x6072, 0)->default_value, (od::Value{0xDC, 0x05}));  // 1500
}

bool have_xmllint() { return std::system("xmllint --version > /dev/null 2>&1") == 0; }

// Runs xmllint on `file`; returns its exit status and output.
std::pair<int, std::string> xmllint(const fs::path& file) {
  const std::string cmd = "xmllint --noout --schema '" + (kXml / "schema" / "device.xsd").string() + "' '" +
                          file.string() + "' 2>&1";
  std::string out;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return {-1, "popen failed"};
  char buf[256];
  while (fgets(buf, sizeof buf, pipe) != nullptr) out += buf;
  return {pclose(pipe), out};
}

class ShippedXmlSchema : public ::testing::TestWithParam<std::string> {};

TEST_P(ShippedXmlSchema, XmllintAccepts) {
  if (!have_xmllint()) GTEST_SKIP() << "xmllint not installed";
  auto [status, out] = xmllint(kXml / GetParam());
  EXPECT_EQ(status, 0) << out;
}

std::vector<std::string> shipped_xml() {
  std::vector<std::string> out;
  for (const char* dir : {"devices", "profiles"}) {
    for (const auto& f : xml_files(kXml / dir)) out.push_back(std::string(dir) + "/" + f);
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Xml, ShippedXmlSchema, ::testing::ValuesIn(shipped_xml()), test_name);

TEST(ShippedXmlSchema, XmllintRejectsABadFile) {
  // Guards the test above: xmllint must fail on a file that breaks the schema.
  if (!have_xmllint()) GTEST_SKIP() << "xmllint not installed";
  const fs::path bad = fs::temp_directory_path() / "ecatslave-bad-device.xml";
  {
    FILE* f = std::fopen(bad.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs("<Device formatVersion=\"1\"><Gadget/></Device>\n", f);
    std::fclose(f);
  }
  auto [status, out] = xmllint(bad);
  fs::remove(bad);
  EXPECT_NE(status, 0) << out;
}

}  // namespace
}  // namespace ecat::esi
