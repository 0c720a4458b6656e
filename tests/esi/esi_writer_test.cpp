// ESI writer: schema-valid against ETG.2000 1.14 and 1.17, deterministic, and
// the values land where ETG.2000 puts them (checked by reading the XML back).
#include <gtest/gtest.h>

#include <pugixml.hpp>

#include "esi/esi_writer.hpp"
#include "esi_test_device.hpp"
#include "esi_xmllint.hpp"

namespace ecat::esi {
namespace {

void expect_schema_valid(const std::string& file) {
  if (!test::can_validate_esi()) GTEST_SKIP() << test::why_no_esi_schema();
  for (const auto& schema : test::esi_schemas()) {
    bool ok = false;
    const std::string out = test::xmllint_schema(file, schema, ok);
    EXPECT_TRUE(ok) << schema << ":\n" << out;
  }
}

pugi::xml_node device_of(const pugi::xml_document& doc) {
  return doc.child("EtherCATInfo").child("Descriptions").child("Devices").child("Device");
}

pugi::xml_node find_object(const pugi::xml_node& device, const std::string& index) {
  for (auto o : device.child("Profile").child("Dictionary").child("Objects").children("Object")) {
    if (index == o.child_value("Index")) return o;
  }
  return {};
}

pugi::xml_node find_type(const pugi::xml_node& device, const std::string& name) {
  for (auto t : device.child("Profile").child("Dictionary").child("DataTypes").children("DataType")) {
    if (name == t.child_value("Name")) return t;
  }
  return {};
}

class EsiWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    xml = write_esi(test::make_test_device());
    ASSERT_TRUE(doc.load_string(xml.c_str()));
    dev = device_of(doc);
    ASSERT_TRUE(dev);
  }
  std::string xml;
  pugi::xml_document doc;
  pugi::xml_node dev;
};

TEST_F(EsiWriterTest, ValidatesAgainstBothSchemaVersions) {
  expect_schema_valid(test::write_test_file("esi_writer_test_servo.xml", xml));
}

TEST_F(EsiWriterTest, Deterministic) { EXPECT_EQ(xml, write_esi(test::make_test_device())); }

TEST_F(EsiWriterTest, IdentityAndGroup) {
  auto info = doc.child("EtherCATInfo");
  EXPECT_STREQ(info.child("Vendor").child_value("Id"), "#x00000ABC");
  EXPECT_STREQ(info.child("Vendor").child_value("Name"), "Example & Co");
  EXPECT_STREQ(dev.attribute("Physics").value(), "YY");
  EXPECT_STREQ(dev.child("Type").attribute("ProductCode").value(), "#x00001234");
  EXPECT_STREQ(dev.child("Type").attribute("RevisionNo").value(), "#x00020001");
  EXPECT_STREQ(dev.child_value("Type"), "TS-100");
  EXPECT_STREQ(dev.child("Name").attribute("LcId").value(), "1033");
  EXPECT_STREQ(dev.child_value("GroupType"), "Servo");
  EXPECT_STREQ(dev.child("Profile").child_value("ProfileNo"), "402");
  EXPECT_STREQ(dev.child("Profile").child_value("AddInfo"), "2");
  EXPECT_FALSE(dev.child("Type").attribute("UseLrdLwr"));
}

TEST_F(EsiWriterTest, RecordSubindexZeroTakesSixteenBits) {
  auto dt = find_type(dev, "DT1018");
  ASSERT_TRUE(dt);
  EXPECT_STREQ(dt.child_value("BitSize"), "144");
  auto subs = dt.children("SubItem");
  auto it = subs.begin();
  EXPECT_STREQ(it->child_value("SubIdx"), "0");
  EXPECT_STREQ(it->child_value("Type"), "USINT");
  EXPECT_STREQ(it->child_value("BitSize"), "8");
  EXPECT_STREQ(it->child_value("BitOffs"), "0");
  ++it;
  EXPECT_STREQ(it->child_value("Name"), "Vendor ID");
  EXPECT_STREQ(it->child_value("BitOffs"), "16");
  EXPECT_STREQ(find_object(dev, "#x1018").child_value("BitSize"), "144");
}

TEST_F(EsiWriterTest, ArrayUsesArrayInfo) {
  auto arr = find_type(dev, "DT1600ARR");
  ASSERT_TRUE(arr);
  EXPECT_STREQ(arr.child_value("BaseType"), "UDINT");
  EXPECT_STREQ(arr.child("ArrayInfo").child_value("LBound"), "1");
  EXPECT_STREQ(arr.child("ArrayInfo").child_value("Elements"), "4");
  auto dt = find_type(dev, "DT1600");
  EXPECT_STREQ(dt.child_value("BitSize"), "144");
  int n = 0;
  for (auto s : dt.children("SubItem")) {
    if (n++ == 1) {
      EXPECT_STREQ(s.child_value("Name"), "Elements");
      EXPECT_STREQ(s.child_value("Type"), "DT1600ARR");
      EXPECT_STREQ(s.child_value("BitOffs"), "16");
      EXPECT_STREQ(s.child("Flags").child("Access").attribute("WriteRestrictions").value(), "PreOP");
    }
  }
  EXPECT_EQ(n, 2);
}

TEST_F(EsiWriterTest, ValuesAreLittleEndianHex) {
  EXPECT_STREQ(find_object(dev, "#x1000").child("Info").child_value("DefaultData"), "92010200");
  auto target = find_object(dev, "#x607A").child("Info");
  EXPECT_STREQ(target.child_value("MinData"), "00000080");
  EXPECT_STREQ(target.child_value("MaxData"), "FFFFFF7F");
  EXPECT_STREQ(find_object(dev, "#x1008").child("Info").child_value("DefaultString"), "Test Servo");
  EXPECT_STREQ(find_object(dev, "#x1008").child_value("Type"), "STRING(10)");
}

TEST_F(EsiWriterTest, FlagsFollowTheAccessBits) {
  auto flags = find_object(dev, "#x6040").child("Flags");
  EXPECT_STREQ(flags.child_value("Access"), "rw");
  EXPECT_STREQ(flags.child_value("PdoMapping"), "R");
  EXPECT_STREQ(flags.child_value("Category"), "o");
  EXPECT_STREQ(find_object(dev, "#x1018").child("Flags").child_value("Category"), "m");
  EXPECT_STREQ(find_object(dev, "#x6041").child("Flags").child_value("PdoMapping"), "T");
  auto modes = find_object(dev, "#x6502").child("Flags").child("Access");
  EXPECT_STREQ(modes.attribute("WriteRestrictions").value(), "PreOP_SafeOP");
  EXPECT_FALSE(modes.attribute("ReadRestrictions"));
  int backups = 0;
  for (auto s : find_type(dev, "DT2000").children("SubItem")) {
    backups += s.child("Flags").child("Backup") ? 1 : 0;
  }
  EXPECT_EQ(backups, 1);
}

TEST_F(EsiWriterTest, SyncManagersPdosMailboxDcEeprom) {
  auto sm = dev.child("Sm");
  EXPECT_STREQ(sm.attribute("StartAddress").value(), "#x1000");
  EXPECT_STREQ(sm.attribute("ControlByte").value(), "#x26");
  EXPECT_STREQ(sm.attribute("DefaultSize").value(), "128");
  EXPECT_STREQ(sm.child_value(), "MBoxOut");
  auto tx = dev.child("TxPdo");
  EXPECT_STREQ(tx.attribute("Fixed").value(), "true");
  EXPECT_STREQ(tx.attribute("Sm").value(), "3");
  EXPECT_STREQ(tx.child_value("Index"), "#x1A00");
  auto rx_gap = dev.child("RxPdo").last_child();
  EXPECT_STREQ(rx_gap.child_value("Index"), "#x0");
  EXPECT_STREQ(rx_gap.child_value("BitLen"), "8");
  EXPECT_FALSE(rx_gap.child("Name"));
  auto coe = dev.child("Mailbox").child("CoE");
  EXPECT_STREQ(coe.attribute("CompleteAccess").value(), "true");
  EXPECT_FALSE(dev.child("Mailbox").child("FoE"));
  auto dc = dev.child("Dc").last_child();
  EXPECT_STREQ(dc.child_value("AssignActivate"), "#x0300");
  EXPECT_STREQ(dc.child("CycleTimeSync0").attribute("Factor").value(), "1");
  EXPECT_STREQ(dev.child("Eeprom").child_value("ByteSize"), "2048");
  EXPECT_STREQ(dev.child("Eeprom").child_value("ConfigData"), "050C004464000000000000000000");
  EXPECT_FALSE(dev.child("Eeprom").child("BootStrap"));
}

TEST(EsiWriter, OptionalFeaturesStayValid) {
  auto d = test::make_test_device();
  d.mailbox.foe = true;
  d.mailbox.eoe = true;
  d.bootstrap_supported = true;
  d.esc.no_lrw = true;
  d.dc_op_modes.push_back({"DC-Sync01", "DC Sync0+1", 0x0700, 1, 1000, 2, 500});
  d.identity.group_name.clear();
  d.rx_pdos[0].excludes = {0x1601};
  // Octet string, unicode string, bit types, duplicate entry names.
  od::Object o;
  o.index = 0x2100;
  o.name = "Blob";
  o.entries.push_back({0, "Blob", od::DataType::OctetString, 32, {}, {1, 2, 3, 4}, {}, {}, "", "", 0});
  ASSERT_TRUE(d.dictionary.put(o));
  od::Object r;
  r.index = 0x2101;
  r.name = "Bits";
  r.code = od::ObjectCode::Record;
  r.entries = {{0, "Count", od::DataType::Unsigned8, 8, {}, {2}, {}, {}, "", "", 0},
               {1, "Flag", od::DataType::Bit3, 3, {}, {}, {}, {}, "", "", 0},
               {2, "Flag", od::DataType::UnicodeString, 64, {}, {}, {}, {}, "", "", 0}};
  ASSERT_TRUE(d.dictionary.put(r));
  const std::string xml = write_esi(d);
  EXPECT_NE(xml.find("<Name>ARRAY [0..3] OF BYTE</Name>"), std::string::npos);
  EXPECT_NE(xml.find("<BootStrap>0010800080108000</BootStrap>"), std::string::npos);
  EXPECT_NE(xml.find("UseLrdLwr=\"true\""), std::string::npos);
  EXPECT_NE(xml.find("<Name>SubIndex 002</Name>"), std::string::npos);  // de-duplicated
  expect_schema_valid(test::write_test_file("esi_writer_options.xml", xml));
}

TEST(EsiWriter, EmptyDeviceIsStillValid) {
  od::DeviceDescription d;
  expect_schema_valid(test::write_test_file("esi_writer_empty.xml", write_esi(d)));
}

}  // namespace
}  // namespace ecat::esi
