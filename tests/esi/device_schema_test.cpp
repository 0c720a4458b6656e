// The embedded copies of xml/ and the libxml2 schema check on their own.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "esi/xml_embedded.hpp"
#include "esi/xml_lines.hpp"
#include "esi/xml_schema.hpp"

namespace ecat::esi {
namespace {

std::string read(const std::string& relative) {
  std::ifstream in(std::string(ECAT_SOURCE_DIR) + "/xml/" + relative, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(DeviceSchema, EmbeddedFilesEqualTheSourceTree) {
  for (const char* name : {"schema/device.xsd", "profiles/cia301.xml", "profiles/cia402.xml",
                           "devices/generic-servo.xml"}) {
    auto embedded = find_embedded(name);
    ASSERT_TRUE(embedded.has_value()) << name;
    EXPECT_EQ(*embedded, read(name)) << name;
  }
  EXPECT_FALSE(find_embedded("profiles/none.xml").has_value());
}

TEST(DeviceSchema, ValidatesWithLineNumbers) {
  const SchemaValidator schema(*find_embedded(kEmbeddedSchema));
  EXPECT_TRUE(schema.validate("<Profile formatVersion=\"1\"/>", "p.xml").has_value());
  auto bad = schema.validate("<Profile formatVersion=\"1\">\n\n  <Objects><Object/></Objects>\n</Profile>", "p.xml");
  ASSERT_FALSE(bad.has_value());
  EXPECT_EQ(bad.error().file, "p.xml");
  EXPECT_EQ(bad.error().line, 3);
  EXPECT_EQ(bad.error().message, "schema: Element 'Object': The attribute 'index' is required but missing.");
  auto no_root = schema.validate("<Thing/>", "t.xml");
  ASSERT_FALSE(no_root.has_value());
  EXPECT_EQ(no_root.error().message.rfind("schema: Element 'Thing'", 0), 0u) << no_root.error().message;
}

TEST(DeviceSchema, BrokenSchemaFailsEveryValidation) {
  const SchemaValidator schema("<xs:schema xmlns:xs=\"http://www.w3.org/2001/XMLSchema\"><xs:bogus/></xs:schema>");
  auto r = schema.validate("<Device formatVersion=\"1\"/>", "d.xml");
  ASSERT_FALSE(r.has_value());
  EXPECT_EQ(r.error().line, 0);
  EXPECT_EQ(r.error().message.rfind("schema: the device schema is invalid", 0), 0u) << r.error().message;
}

TEST(DeviceSchema, LineIndex) {
  const LineIndex lines("ab\ncd\n\nef");
  EXPECT_EQ(lines.line_of(0), 1);
  EXPECT_EQ(lines.line_of(2), 1);  // the newline itself
  EXPECT_EQ(lines.line_of(3), 2);
  EXPECT_EQ(lines.line_of(6), 3);
  EXPECT_EQ(lines.line_of(7), 4);
  EXPECT_EQ(lines.line_of(-1), 0);
}

TEST(DeviceSchema, LineIndexCountsEveryXmlLineEnd) {
  // XML 1.0 §2.11: CR LF and a CR alone end a line like LF (CR-only files exist).
  const LineIndex cr("ab\rcd\r\ref");
  EXPECT_EQ(cr.line_of(3), 2);
  EXPECT_EQ(cr.line_of(7), 4);
  const LineIndex crlf("ab\r\ncd\r\n\r\nef");
  EXPECT_EQ(crlf.line_of(2), 1);  // the CR of CR LF is still line 1
  EXPECT_EQ(crlf.line_of(4), 2);
  EXPECT_EQ(crlf.line_of(10), 4);
}

}  // namespace
}  // namespace ecat::esi
