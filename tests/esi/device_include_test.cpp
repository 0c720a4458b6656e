// Includes: override / extend / remove of included objects, explicit values
// winning over derived ones, the built-in profile fallback, and errors in
// included files reported against those files.
#include <gtest/gtest.h>

#include "esi/device_loader.hpp"

namespace ecat::esi {
namespace {

using od::Value;

const std::string kDir = std::string(ECAT_SOURCE_DIR) + "/tests/data/devices/";

od::DeviceDescription load_fixture(const std::string& name) {
  auto dev = load_device_file(kDir + name);
  EXPECT_TRUE(dev.has_value()) << dev.error().to_string();
  return dev ? std::move(*dev) : od::DeviceDescription{};
}

TEST(DeviceInclude, LaterAttributesOverrideIncludedOnes) {
  const auto dev = load_fixture("override-device.xml");
  const od::Entry* gain = dev.dictionary.find(0x2000, 0);
  ASSERT_NE(gain, nullptr);
  EXPECT_EQ(gain->name, "Gain");                    // kept from the profile
  EXPECT_EQ(gain->default_value, (Value{50, 0}));   // overridden
  EXPECT_EQ(gain->max_value, (Value{100, 0}));      // kept
  EXPECT_EQ(gain->unit, "mA");                      // added
  EXPECT_EQ(gain->access.bits, od::Access::kRw);
}

TEST(DeviceInclude, ArraysAndRecordsAreExtended) {
  const auto dev = load_fixture("override-device.xml");
  const od::Object* limits = dev.dictionary.find(0x2001);
  ASSERT_NE(limits, nullptr);
  ASSERT_EQ(limits->entries.size(), 4u);
  EXPECT_EQ(limits->entries[0].default_value, Value{3});
  EXPECT_EQ(limits->entries[1].name, "SubIndex 001");
  EXPECT_EQ(limits->entries[1].default_value, (Value{5, 0, 0, 0}));  // inherited array default
  EXPECT_EQ(limits->entries[3].name, "Extra");
  EXPECT_EQ(limits->entries[3].default_value, (Value{0xFF, 0xFF, 0xFF, 0xFF}));
  const od::Object* settings = dev.dictionary.find(0x2003);
  ASSERT_NE(settings, nullptr);
  ASSERT_EQ(settings->entries.size(), 3u);
  EXPECT_EQ(settings->entries[0].default_value, Value{2});
  EXPECT_EQ(settings->entries[1].name, "Mode");
  EXPECT_EQ(settings->entries[2].type, od::DataType::Integer16);
  EXPECT_EQ(settings->entries[2].default_value, (Value{0xD4, 0xFE}));  // -300
}

TEST(DeviceInclude, RemoveDeletesAnIncludedObject) {
  const auto dev = load_fixture("override-device.xml");
  EXPECT_EQ(dev.dictionary.find(0x2002), nullptr);
}

TEST(DeviceInclude, ExplicitValuesWinOverDerivedOnes) {
  const auto dev = load_fixture("override-device.xml");
  const od::Object* id = dev.dictionary.find(0x1018);
  ASSERT_NE(id, nullptr);
  ASSERT_EQ(id->entries.size(), 3u);  // only the subindices the file lists
  EXPECT_EQ(id->entries[1].default_value, (Value{0xFE, 0xCA, 0, 0}));   // explicit
  EXPECT_EQ(id->entries[2].default_value, (Value{0x01, 0, 0, 0}));      // derived productCode
  EXPECT_EQ(dev.identity.vendor_id, 0x12345678u);
  // 1000h is created even without a profile; 1008h from the name.
  ASSERT_NE(dev.dictionary.find(0x1000, 0), nullptr);
  EXPECT_EQ(dev.dictionary.find(0x1008, 0)->bit_length, 13u * 8);
}

TEST(DeviceInclude, MissingProfileFallsBackToTheBuiltInOne) {
  const auto dev = load_fixture("embedded-profile-fallback.xml");
  const od::Entry* cw = dev.dictionary.find(0x6040, 0);
  ASSERT_NE(cw, nullptr);
  EXPECT_EQ(cw->name, "Controlword");
  EXPECT_EQ(dev.identity.name, "Fallback");
}

TEST(DeviceInclude, ErrorInIncludedFileNamesThatFile) {
  auto dev = load_device_file(kDir + "includes-bad-profile.xml");
  ASSERT_FALSE(dev.has_value());
  EXPECT_EQ(dev.error().file, kDir + "bad-type-profile.xml");
  EXPECT_EQ(dev.error().line, 5);
  EXPECT_EQ(dev.error().message, "unknown data type 'UNSIGNED17'");
}

TEST(DeviceInclude, MissingIncludeFile) {
  auto dev = load_device_file(kDir + "missing-include.xml");
  ASSERT_FALSE(dev.has_value());
  EXPECT_EQ(dev.error().to_string(),
            kDir + "missing-include.xml:4: include file 'no-such-file.xml' not found (looked for " + kDir +
                "no-such-file.xml)");
}

TEST(DeviceInclude, IncludeCycle) {
  auto dev = load_device_file(kDir + "cycle-a.xml");
  ASSERT_FALSE(dev.has_value());
  EXPECT_EQ(dev.error().file, kDir + "cycle-b.xml");
  EXPECT_EQ(dev.error().line, 4);
  EXPECT_EQ(dev.error().message,
            "include cycle: './cycle-a.xml' includes itself (via " + kDir + "cycle-a.xml)");
}

TEST(DeviceInclude, StringSourceResolvesIncludesAgainstItsName) {
  const std::string xml = R"(<Device formatVersion="1">
  <Include href="base-profile.xml"/>
</Device>
)";
  auto dev = load_device_string(xml, kDir + "from-string.xml");
  ASSERT_TRUE(dev.has_value()) << dev.error().to_string();
  EXPECT_NE(dev->dictionary.find(0x2000), nullptr);
}

TEST(DeviceInclude, DeclaredAssignmentObjectsAreFilledExplicitOnesKept) {
  const std::string xml = R"(<Device formatVersion="1">
  <Identity name="Assign"/>
  <SyncManagers>
    <Sm index="0" type="MailboxOut" start="#x1000" size="64" control="#x26"/>
    <Sm index="1" type="MailboxIn" start="#x1040" size="64" control="#x22"/>
    <Sm index="2" type="Outputs" start="#x1100" control="#x64"/>
    <Sm index="3" type="Inputs" start="#x1200" control="#x20"/>
  </SyncManagers>
  <Objects>
    <Object index="#x1C12" name="RxPDO assign" access="ro"/>
    <Object index="#x1C13" name="TxPDO assign" code="ARRAY" type="UNSIGNED16" count="1" default="#x1A07"/>
    <Object index="#x7000" name="Out" type="UNSIGNED8" access="rw" pdo="rx"/>
  </Objects>
  <RxPdo index="#x1600" sm="2"><Entry index="#x7000" bits="8"/></RxPdo>
  <RxPdo index="#x1601"><Entry index="#x7000" bits="8"/></RxPdo>
</Device>
)";
  auto dev = load_device_string(xml, kDir + "assign.xml");
  ASSERT_TRUE(dev.has_value()) << dev.error().to_string();
  const od::Object* rx = dev->dictionary.find(0x1C12);
  ASSERT_NE(rx, nullptr);
  EXPECT_EQ(rx->name, "RxPDO assign");
  ASSERT_EQ(rx->entries.size(), 3u);
  EXPECT_EQ(rx->entries[0].default_value, Value{1});
  EXPECT_EQ(rx->entries[0].access.bits, od::Access::kRo);  // the declared access
  EXPECT_EQ(rx->entries[1].access.bits, od::Access::kRo);
  EXPECT_EQ(rx->entries[1].default_value, (Value{0x00, 0x16}));
  const od::Object* tx = dev->dictionary.find(0x1C13);
  ASSERT_NE(tx, nullptr);
  ASSERT_EQ(tx->entries.size(), 2u);
  EXPECT_EQ(tx->entries[1].default_value, (Value{0x07, 0x1A}));  // as written
  const od::Object* types = dev->dictionary.find(0x1C00);
  ASSERT_NE(types, nullptr);
  ASSERT_EQ(types->entries.size(), 5u);
  EXPECT_EQ(types->entries[3].default_value, Value{3});
}

}  // namespace
}  // namespace ecat::esi
