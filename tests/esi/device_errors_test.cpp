// Every check of the device loader (docs/device-format.md "Checks and error
// messages") on a tiny inline device: the exact file, line and message.
#include <gtest/gtest.h>

#include "esi/device_loader.hpp"

namespace ecat::esi {
namespace {

const std::string kName = std::string(ECAT_SOURCE_DIR) + "/tests/data/devices/inline.xml";

// Lines 1-2 are fixed; `body` starts on line 3.
std::string device(std::string_view body) {
  return "<Device formatVersion=\"1\">\n  <Identity vendorId=\"0\" name=\"T\"/>\n" + std::string(body) +
         "</Device>\n";
}

// Four SMs (lines 3-8) as in the generic servo; what follows starts on line 9.
std::string with_sms(std::string_view rest) {
  return device(R"(  <SyncManagers>
    <Sm index="0" type="MailboxOut" start="#x1000" size="128" control="#x26"/>
    <Sm index="1" type="MailboxIn" start="#x1080" size="128" control="#x22"/>
    <Sm index="2" type="Outputs" start="#x1100" maxSize="8" control="#x64"/>
    <Sm index="3" type="Inputs" start="#x1200" maxSize="8" control="#x20"/>
  </SyncManagers>
)" + std::string(rest));
}

// Objects for PDO tests: lines 9-14.
constexpr std::string_view kPdoObjects = R"(  <Objects>
    <Object index="#x7000" name="Out16" type="UNSIGNED16" access="rw" pdo="rx"/>
    <Object index="#x6000" name="In16" type="UNSIGNED16" pdo="tx"/>
    <Object index="#x2000" name="Param" type="UNSIGNED32" access="rw"/>
    <Object index="#x7010" name="OutArr" code="ARRAY" type="UNSIGNED8" count="2" access="rw" pdo="rx"/>
  </Objects>
)";

LoadError error_of(const std::string& xml) {
  auto dev = load_device_string(xml, kName);
  EXPECT_FALSE(dev.has_value()) << "loaded although it should not";
  if (dev) return {};
  EXPECT_EQ(dev.error().file, kName);
  return dev.error();
}

TEST(DeviceErrors, TheTemplatesLoad) {
  auto dev = load_device_string(with_sms(std::string(kPdoObjects) + R"(  <RxPdo index="#x1600" sm="2">
    <Entry index="#x7000" bits="16"/>
  </RxPdo>
)"), kName);
  ASSERT_TRUE(dev.has_value()) << dev.error().to_string();
  EXPECT_EQ(dev->rx_pdos.size(), 1u);
}

TEST(DeviceErrors, MalformedXml) {
  const LoadError e = error_of(device("  <Objects>\n    <Object index=\"1\"\n  </Objects>\n"));
  EXPECT_EQ(e.line, 5);
  EXPECT_EQ(e.message.rfind("XML parse error: ", 0), 0u) << e.message;
}

TEST(DeviceErrors, UnknownElement) {
  const LoadError e = error_of(device("  <Objects/>\n  <Gadget/>\n"));
  EXPECT_EQ(e.line, 4);
  EXPECT_EQ(e.message.rfind("schema: Element 'Gadget': This element is not expected.", 0), 0u) << e.message;
}

TEST(DeviceErrors, UnknownAttribute) {
  const LoadError e = error_of(device("  <Esc ramSize=\"4096\" colour=\"blue\"/>\n"));
  EXPECT_EQ(e.line, 3);
  EXPECT_EQ(e.message, "schema: Element 'Esc', attribute 'colour': The attribute 'colour' is not allowed.");
}

TEST(DeviceErrors, BadNumber) {
  const LoadError e = error_of(device("  <Esc ramSize=\"lots\"/>\n"));
  EXPECT_EQ(e.line, 3);
  EXPECT_NE(e.message.find("attribute 'ramSize'"), std::string::npos) << e.message;
}

TEST(DeviceErrors, UnsupportedFormatVersion) {
  auto dev = load_device_string("<Device formatVersion=\"2\"/>\n", kName);
  ASSERT_FALSE(dev.has_value());
  EXPECT_EQ(dev.error().to_string(), kName + ":1: unsupported formatVersion '2' (this loader reads 1)");
}

TEST(DeviceErrors, UnknownDataType) {
  const LoadError e = error_of(device(R"(  <Objects>
    <Object index="#x2000" name="X" type="UINT16"/>
  </Objects>
)"));
  EXPECT_EQ(e.line, 4);
  EXPECT_EQ(e.message, "unknown data type 'UINT16'");
}

TEST(DeviceErrors, UnknownStructuredType) {
  const LoadError e = error_of(device(R"(  <Objects>
    <Object index="#x2000" name="X" code="RECORD" type="STRUCT"/>
  </Objects>
)"));
  EXPECT_EQ(e.line, 4);
  EXPECT_EQ(e.message, "unknown structured type 'STRUCT'");
}

TEST(DeviceErrors, DuplicateIndex) {
  const LoadError e = error_of(device(R"(  <Objects>
    <Object index="#x2000" name="X" type="UNSIGNED8"/>
    <Object index="8192" name="Y" type="UNSIGNED8"/>
  </Objects>
)"));
  EXPECT_EQ(e.line, 5);
  EXPECT_EQ(e.message, "duplicate object 2000h (first defined at line 4)");
}

TEST(DeviceErrors, DuplicateSubindex) {
  const LoadError e = error_of(device(R"(  <Objects>
    <Object index="#x2000" name="X" code="RECORD">
      <Entry sub="1" name="A" type="UNSIGNED8"/>
      <Entry sub="0x1" name="B" type="UNSIGNED8"/>
    </Object>
  </Objects>
)"));
  EXPECT_EQ(e.line, 6);
  EXPECT_EQ(e.message, "duplicate subindex 1 in object 2000h");
}

TEST(DeviceErrors, RemoveOfUnknownObject) {
  const LoadError e = error_of(device("  <Objects>\n    <Remove index=\"#x2000\"/>\n  </Objects>\n"));
  EXPECT_EQ(e.line, 4);
  EXPECT_EQ(e.message, "Remove of object 2000h, which is not defined");
}

TEST(DeviceErrors, RecordEntryWithoutType) {
  const LoadError e = error_of(device(R"(  <Objects>
    <Object index="#x2000" name="X" code="RECORD">
      <Entry sub="1" name="A"/>
    </Object>
  </Objects>
)"));
  EXPECT_EQ(e.line, 5);
  EXPECT_EQ(e.message, "2000h:01 has no type");
}

TEST(DeviceErrors, ArrayElementOfAnotherType) {
  const LoadError e = error_of(device(R"(  <Objects>
    <Object index="#x2000" name="X" code="ARRAY" type="UNSIGNED8" count="2">
      <Entry sub="2" type="UNSIGNED16"/>
    </Object>
  </Objects>
)"));
  EXPECT_EQ(e.line, 5);
  EXPECT_EQ(e.message, "2000h:02 has type UNSIGNED16 but must be UNSIGNED8");
}

TEST(DeviceErrors, VarWithEntries) {
  const LoadError e = error_of(device(R"(  <Objects>
    <Object index="#x2000" name="X" type="UNSIGNED8">
      <Entry sub="1" type="UNSIGNED8"/>
    </Object>
  </Objects>
)"));
  EXPECT_EQ(e.line, 5);
  EXPECT_EQ(e.message, "2000h is a VAR and cannot have Entry elements (use code=\"ARRAY\" or \"RECORD\")");
}

TEST(DeviceErrors, BitsDifferFromType) {
  const LoadError e = error_of(device(R"(  <Objects>
    <Object index="#x2000" name="X" type="UNSIGNED16" bits="12"/>
  </Objects>
)"));
  EXPECT_EQ(e.line, 4);
  EXPECT_EQ(e.message, "2000h:00: bits 12 does not match the size of UNSIGNED16 (16 bits)");
}

TEST(DeviceErrors, ValueDoesNotFitItsType) {
  const LoadError e = error_of(device(R"(  <Objects>
    <Object index="#x2000" name="X" type="UNSIGNED8" default="256"/>
  </Objects>
)"));
  EXPECT_EQ(e.line, 4);
  EXPECT_EQ(e.message, "2000h:00 default: value 256 does not fit UNSIGNED8");
}

TEST(DeviceErrors, NegativeValueForUnsigned) {
  const LoadError e = error_of(device(R"(  <Objects>
    <Object index="#x2000" name="X" code="ARRAY" type="UNSIGNED32" count="1" min="-1"/>
  </Objects>
)"));
  EXPECT_EQ(e.line, 4);
  EXPECT_EQ(e.message, "2000h:01 min: value -1 does not fit UNSIGNED32");
}

TEST(DeviceErrors, DefaultAboveMax) {
  const LoadError e = error_of(device(R"(  <Objects>
    <Object index="#x2000" name="X" type="INTEGER16" min="-100" max="100" default="150"/>
  </Objects>
)"));
  EXPECT_EQ(e.line, 4);
  EXPECT_EQ(e.message, "2000h:00: default 150 is above max 100");
}

TEST(DeviceErrors, DefaultBelowMin) {
  const LoadError e = error_of(device(R"(  <Objects>
    <Object index="#x2000" name="X" type="INTEGER16" min="-100" max="100" default="-101"/>
  </Objects>
)"));
  EXPECT_EQ(e.message, "2000h:00: default -101 is below min -100");
}

TEST(DeviceErrors, StringLongerThanItsLength) {
  const LoadError e = error_of(device(R"(  <Objects>
    <Object index="#x2000" name="X" type="VISIBLE_STRING" length="4" default="toolong"/>
  </Objects>
)"));
  EXPECT_EQ(e.line, 4);
  EXPECT_EQ(e.message, "2000h:00 default: string 'toolong' is 7 bytes, longer than its length 4");
}

TEST(DeviceErrors, PdoEntryOfNonMappableObject) {
  const LoadError e = error_of(with_sms(std::string(kPdoObjects) + R"(  <RxPdo index="#x1600" sm="2">
    <Entry index="#x2000" bits="32"/>
  </RxPdo>
)"));
  EXPECT_EQ(e.line, 16);
  EXPECT_EQ(e.message, "PDO 1600h entry 2000h:00: 2000h:00 is not RxPDO-mappable");
}

TEST(DeviceErrors, PdoEntryOfWrongDirection) {
  const LoadError e = error_of(with_sms(std::string(kPdoObjects) + R"(  <TxPdo index="#x1A00" sm="3">
    <Entry index="#x6000" bits="16"/>
    <Entry index="#x7000" bits="16"/>
  </TxPdo>
)"));
  EXPECT_EQ(e.line, 17);
  EXPECT_EQ(e.message, "PDO 1A00h entry 7000h:00: 7000h:00 is not TxPDO-mappable");
}

TEST(DeviceErrors, PdoEntryOfUnknownObjectOrSubindex) {
  LoadError e = error_of(with_sms(std::string(kPdoObjects) + R"(  <RxPdo index="#x1600">
    <Entry index="#x7001" bits="16"/>
  </RxPdo>
)"));
  EXPECT_EQ(e.line, 16);
  EXPECT_EQ(e.message, "PDO 1600h entry 7001h:00: no such object");
  e = error_of(with_sms(std::string(kPdoObjects) + R"(  <RxPdo index="#x1600">
    <Entry index="#x7010" sub="3" bits="8"/>
  </RxPdo>
)"));
  EXPECT_EQ(e.line, 16);
  EXPECT_EQ(e.message, "PDO 1600h entry 7010h:03: no such subindex");
}

TEST(DeviceErrors, PdoEntryBitLengthDiffers) {
  const LoadError e = error_of(with_sms(std::string(kPdoObjects) + R"(  <RxPdo index="#x1600">
    <Entry index="#x7000" bits="8"/>
  </RxPdo>
)"));
  EXPECT_EQ(e.line, 16);
  EXPECT_EQ(e.message, "PDO 1600h entry 7000h:00: bits 8 differ from the object's size (16 bits)");
}

TEST(DeviceErrors, PdoLongerThanItsSm) {
  // SM2 maxSize is 8 bytes; 16 + 8 + 8 + 32 + 16 bits = 10 bytes.
  const LoadError e = error_of(with_sms(std::string(kPdoObjects) + R"(  <RxPdo index="#x1600" sm="2">
    <Entry index="#x7000" bits="16"/>
    <Entry index="#x7010" sub="1" bits="8"/>
    <Entry index="#x7010" sub="2" bits="8"/>
    <Entry index="0" bits="32"/>
    <Entry index="#x7000" bits="16"/>
  </RxPdo>
)"));
  EXPECT_EQ(e.line, 15);
  EXPECT_EQ(e.message, "PDO 1600h is 10 bytes, longer than SyncManager 2's maximum 8");
}

TEST(DeviceErrors, AssignedPdosLongerThanTheirSm) {
  const LoadError e = error_of(with_sms(std::string(kPdoObjects) + R"(  <RxPdo index="#x1600" sm="2">
    <Entry index="0" bits="48"/>
  </RxPdo>
  <RxPdo index="#x1601" sm="2">
    <Entry index="#x7000" bits="16"/>
    <Entry index="#x7000" bits="16"/>
  </RxPdo>
)"));
  EXPECT_EQ(e.line, 18);
  EXPECT_EQ(e.message, "PDOs assigned to SyncManager 2 need 10 bytes, more than its maximum 8");
}

TEST(DeviceErrors, PdoIndexOutOfRangeAndWrongSm) {
  LoadError e = error_of(with_sms(std::string(kPdoObjects) + "  <TxPdo index=\"#x1600\"/>\n"));
  EXPECT_EQ(e.line, 15);
  EXPECT_EQ(e.message, "TxPdo index 1600h is outside 1A00h..1BFFh");
  e = error_of(with_sms(std::string(kPdoObjects) + "  <RxPdo index=\"#x1600\" sm=\"3\"/>\n"));
  EXPECT_EQ(e.message, "PDO 1600h: SyncManager 3 is not an Outputs SyncManager");
}

TEST(DeviceErrors, DuplicatePdo) {
  const LoadError e = error_of(with_sms("  <RxPdo index=\"#x1600\"/>\n  <RxPdo index=\"#x1600\"/>\n"));
  EXPECT_EQ(e.line, 10);
  EXPECT_EQ(e.message, "duplicate PDO 1600h (first defined at line 9)");
}

TEST(DeviceErrors, SyncManagersOverlap) {
  // SM2 is buffered (control bits 1:0 = 00): 3 x 256 bytes from 0x1100 reach 0x13FF.
  const LoadError e = error_of(device(R"(  <SyncManagers>
    <Sm index="0" type="MailboxOut" start="#x1000" size="128" control="#x26"/>
    <Sm index="1" type="MailboxIn" start="#x1080" size="128" control="#x22"/>
    <Sm index="2" type="Outputs" start="#x1100" maxSize="256" control="#x64"/>
    <Sm index="3" type="Inputs" start="#x1300" maxSize="16" control="#x20"/>
  </SyncManagers>
)"));
  EXPECT_EQ(e.line, 7);
  EXPECT_EQ(e.message, "SyncManager 3 (0x1300..0x132f) overlaps SyncManager 2 (0x1100..0x13ff)");
}

TEST(DeviceErrors, SyncManagerOutsideProcessRam) {
  const LoadError e = error_of(device(R"(  <Esc ramSize="1024"/>
  <SyncManagers>
    <Sm index="0" type="MailboxOut" start="#x1000" size="128" control="#x26"/>
    <Sm index="1" type="MailboxIn" start="#x1390" size="128" control="#x22"/>
  </SyncManagers>
)"));
  EXPECT_EQ(e.line, 6);
  EXPECT_EQ(e.message, "SyncManager 1 (0x1390..0x140f) is outside the process RAM 0x1000..0x13ff");
}

TEST(DeviceErrors, SyncManagerBelowProcessRam) {
  const LoadError e = error_of(device(R"(  <SyncManagers>
    <Sm index="0" type="MailboxOut" start="#x0F00" size="128" control="#x26"/>
  </SyncManagers>
)"));
  EXPECT_EQ(e.line, 4);
  EXPECT_EQ(e.message, "SyncManager 0 (0x0f00..0x0f7f) is outside the process RAM 0x1000..0x2fff");
}

TEST(DeviceErrors, SyncManagerIndexChecks) {
  LoadError e = error_of(device(R"(  <Esc syncManagers="2"/>
  <SyncManagers>
    <Sm index="2" type="Outputs" start="#x1100" control="#x64"/>
  </SyncManagers>
)"));
  EXPECT_EQ(e.line, 5);
  EXPECT_EQ(e.message, "SyncManager 2 does not exist: the ESC has 2 (Esc syncManagers)");
  e = error_of(device(R"(  <SyncManagers>
    <Sm index="0" type="MailboxOut" start="#x1000" size="128" control="#x26"/>
    <Sm index="0" type="MailboxIn" start="#x1080" size="128" control="#x22"/>
  </SyncManagers>
)"));
  EXPECT_EQ(e.line, 5);
  EXPECT_EQ(e.message, "duplicate SyncManager 0");
}

TEST(DeviceErrors, TooManyFmmus) {
  const LoadError e = error_of(device(R"(  <Esc fmmus="1"/>
  <Fmmus><Fmmu usage="Outputs"/><Fmmu usage="Inputs"/></Fmmus>
)"));
  EXPECT_EQ(e.line, 4);
  EXPECT_EQ(e.message, "2 FMMUs listed but the ESC has 1 (Esc fmmus)");
}

}  // namespace
}  // namespace ecat::esi

namespace ecat::esi {
namespace {

TEST(DeviceErrors, ExcludesUnknownPdo) {
  const LoadError e = error_of(with_sms(R"(  <RxPdo index="#x1600" excludes="#x1601 #x1602"/>
  <RxPdo index="#x1601"/>
)"));
  EXPECT_EQ(e.line, 9);
  EXPECT_EQ(e.message, "PDO 1600h excludes PDO 1602h, which is not defined");
}

TEST(DeviceErrors, MailboxSmWithoutSize) {
  const LoadError e = error_of(device(R"(  <SyncManagers>
    <Sm index="0" type="MailboxOut" start="#x1000" control="#x26"/>
  </SyncManagers>
)"));
  EXPECT_EQ(e.line, 4);
  EXPECT_EQ(e.message, "mailbox SyncManager 0 needs a size");
}

TEST(DeviceErrors, ObjectWithoutName) {
  const LoadError e = error_of(device("  <Objects>\n    <Object index=\"#x2000\" type=\"UNSIGNED8\"/>\n  </Objects>\n"));
  EXPECT_EQ(e.line, 4);
  EXPECT_EQ(e.message, "object 2000h has no name");
}

}  // namespace
}  // namespace ecat::esi

namespace ecat::esi {
namespace {

TEST(DeviceErrors, ArrayEntryBeyondCount) {
  const LoadError e = error_of(device(R"(  <Objects>
    <Object index="#x2000" name="X" code="ARRAY" type="UNSIGNED8" count="2">
      <Entry sub="3"/>
    </Object>
  </Objects>
)"));
  EXPECT_EQ(e.line, 5);
  EXPECT_EQ(e.message, "2000h: subindex 3 is beyond the array's count 2");
}

TEST(DeviceErrors, NumberOutOfRangeForItsField) {
  const LoadError e = error_of(device(R"(  <SyncManagers>
    <Sm index="0" type="MailboxOut" start="#x10000" size="128" control="#x26"/>
  </SyncManagers>
)"));
  EXPECT_EQ(e.line, 4);
  EXPECT_EQ(e.message, "start '#x10000' is out of range (0..65535)");
}

TEST(DeviceErrors, RemovedObjectMayBeRedefinedInTheSameFile) {
  auto dev = load_device_string(device(R"(  <Objects>
    <Object index="#x2000" name="X" type="UNSIGNED8"/>
    <Remove index="#x2000"/>
    <Object index="#x2000" name="Y" type="UNSIGNED16"/>
  </Objects>
)"), kName);
  ASSERT_TRUE(dev.has_value()) << dev.error().to_string();
  EXPECT_EQ(dev->dictionary.find(0x2000)->name, "Y");
  EXPECT_EQ(dev->dictionary.find(0x2000)->type, od::DataType::Unsigned16);
}

TEST(DeviceErrors, OversizedInputIsRejectedNotParsed) {
  const std::string big(65u << 20, ' ');
  auto dev = load_device_string(big, kName);
  ASSERT_FALSE(dev.has_value());
  EXPECT_EQ(dev.error().to_string(), kName + ": file is larger than 67108864 bytes");
}

}  // namespace
}  // namespace ecat::esi
