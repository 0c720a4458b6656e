// Twin repairs met in the vendor files users bring (docs/twins.md "Vendor
// files users bring"), each in a small ESI written for this test in the shape
// the vendor file has: a Sanyo Denki Type@SerialNo that 1018h:04 repeats, a
// Bohign ConfigData with PDI type 0 next to a CoE mailbox and a 1018h whose
// SI0 is 0, and a Weidmueller coupler as IgH's `ethercat xml` writes it (Sm
// without text, PDOs with an empty Name). Each: what the twin holds, the
// warning and its line, and that the twin loads as our device file.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "esi/device_loader.hpp"
#include "esi/esi_reader.hpp"
#include "esi/esi_writer.hpp"
#include "esi/esi_writer_device_xml.hpp"
#include "od/firmware.hpp"
#include "twin_warnings.hpp"

namespace ecat::esi {
namespace {

using namespace test;

// One device; `type_attrs` go on <Type>, `body` after GroupType.
std::string esi(const std::string& type_attrs, const std::string& body) {
  return R"(<?xml version="1.0"?>
<EtherCATInfo Version="1.2">
  <Vendor><Id>#x000001B9</Id><Name>Brands</Name></Vendor>
  <Descriptions>
    <Groups><Group><Type>G</Type><Name>G</Name></Group></Groups>
    <Devices>
      <Device Physics="YY">
        <Type ProductCode="#x00000002" RevisionNo="#x00000000")" +
         type_attrs + R"(>B-1</Type>
        <Name>B-1</Name>
        <GroupType>G</GroupType>
)" + body + R"(
      </Device>
    </Devices>
  </Descriptions>
</EtherCATInfo>
)";
}

// A dictionary with 1018h (SI0 default `si0`, 1018h:04 default `serial`).
std::string identity_profile(const std::string& si0, const std::string& serial) {
  return R"(
        <Profile><ProfileNo>402</ProfileNo><Dictionary>
          <DataTypes>
            <DataType><Name>USINT</Name><BitSize>8</BitSize></DataType>
            <DataType><Name>UDINT</Name><BitSize>32</BitSize></DataType>
            <DataType><Name>DT1018</Name><BitSize>144</BitSize>
              <SubItem><SubIdx>0</SubIdx><Name>SubIndex 000</Name><Type>USINT</Type><BitSize>8</BitSize><BitOffs>0</BitOffs><Flags><Access>ro</Access></Flags></SubItem>
              <SubItem><SubIdx>1</SubIdx><Name>Vendor ID</Name><Type>UDINT</Type><BitSize>32</BitSize><BitOffs>16</BitOffs><Flags><Access>ro</Access></Flags></SubItem>
              <SubItem><SubIdx>2</SubIdx><Name>Product code</Name><Type>UDINT</Type><BitSize>32</BitSize><BitOffs>48</BitOffs><Flags><Access>ro</Access></Flags></SubItem>
              <SubItem><SubIdx>3</SubIdx><Name>Revision</Name><Type>UDINT</Type><BitSize>32</BitSize><BitOffs>80</BitOffs><Flags><Access>ro</Access></Flags></SubItem>
              <SubItem><SubIdx>4</SubIdx><Name>Serial number</Name><Type>UDINT</Type><BitSize>32</BitSize><BitOffs>112</BitOffs><Flags><Access>ro</Access></Flags></SubItem>
            </DataType>
          </DataTypes>
          <Objects>
            <Object><Index>#x1018</Index><Name>Identity</Name><Type>DT1018</Type><BitSize>144</BitSize>
              <Info>
                <SubItem><Name>SubIndex 000</Name><Info><DefaultData>)" +
         si0 + R"(</DefaultData></Info></SubItem>
                <SubItem><Name>Vendor ID</Name><Info><DefaultData>B9010000</DefaultData></Info></SubItem>
                <SubItem><Name>Product code</Name><Info><DefaultData>02000000</DefaultData></Info></SubItem>
                <SubItem><Name>Revision</Name><Info><DefaultData>00000000</DefaultData></Info></SubItem>
                <SubItem><Name>Serial number</Name><Info><DefaultData>)" +
         serial + R"(</DefaultData></Info></SubItem>
              </Info>
              <Flags><Access>ro</Access></Flags></Object>
          </Objects>
        </Dictionary></Profile>)";
}

const char* const kMailbox = R"(
        <Sm MinSize="34" MaxSize="192" DefaultSize="128" StartAddress="#x1000" ControlByte="#x26" Enable="1">MBoxOut</Sm>
        <Sm MinSize="34" MaxSize="192" DefaultSize="128" StartAddress="#x1100" ControlByte="#x22" Enable="1">MBoxIn</Sm>
        <Mailbox><CoE/></Mailbox>)";

std::uint32_t u32(const od::Value& v) {
  std::uint32_t x = 0;
  for (std::size_t i = 0; i < v.size() && i < 4; ++i) x |= static_cast<std::uint32_t>(v[i]) << (8 * i);
  return x;
}

TEST(TwinUserBrands, TheSerialNumberOfTheTypeSurvivesTheReEmittedEsi) {
  // Sanyo Denki RS2: Type SerialNo="#x20110111", 1018h:04 = 11011120 (the same, little-endian).
  const std::string text = esi(R"( SerialNo="#x20110111")", identity_profile("04", "11011120"));
  Read r = read(text);
  EXPECT_EQ(r.d.identity.serial, 0x20110111u);
  EXPECT_FALSE(warns_about(r.warnings, "1018h:04")) << all(r.warnings);
  const std::string again = write_esi(r.d);
  EXPECT_NE(again.find("SerialNo=\"#x20110111\""), std::string::npos) << again;
  Read back = read(again);
  EXPECT_EQ(back.d.identity.serial, 0x20110111u);
  EXPECT_FALSE(warns_about(back.warnings, "1018h:04")) << all(back.warnings);
  EXPECT_EQ(u32(back.d.dictionary.find(0x1018, 4)->default_value), 0x20110111u);
  // Without a serial the attribute is not written (ETG.2000: optional).
  EXPECT_EQ(write_esi(read(esi("", identity_profile("04", "00000000"))).d).find("SerialNo"), std::string::npos);
}

TEST(TwinUserBrands, IdentitySubindexZeroBelowItsEntriesCoversThem) {
  // Bohign DM556EC: 1018h SI0 "00" next to 1018h:01-04.
  const std::string text = esi("", identity_profile("00", "00000000") + kMailbox);
  Read r = read(text);
  const od::Entry* si0 = r.d.dictionary.find(0x1018, 0);
  ASSERT_NE(si0, nullptr);
  EXPECT_EQ(si0->default_value, od::Value({4}));
  EXPECT_TRUE(has_warning(r.warnings, line_of(text, "<Index>#x1018"),
                          "1018h:00 default #x00 is below the identity entries 1018h:01-04 the object defines; "
                          "SI0 is 4"))
      << all(r.warnings);
  auto back = load_device_string(write_device_xml(r.d), "twin.xml");
  ASSERT_TRUE(back) << back.error().to_string();
  EXPECT_EQ(back->dictionary.find(0x1018, 0)->default_value, od::Value({4}));
  // SI0 4 as it should be: no warning.
  EXPECT_FALSE(warns_about(read(esi("", identity_profile("04", "00000000"))).warnings, "1018h:00"));
}

TEST(TwinUserBrands, PdiTypeZeroNextToAMailboxStillRunsTheFirmware) {
  // Bohign: ConfigData 003C0000FF03...: 0x0140 = 00h (PDI deactivated), 0x0141 = 3Ch.
  const std::string text = esi("", std::string(kMailbox) + R"(
        <Eeprom><ByteSize>2048</ByteSize><ConfigData>003C0000FF0300000000</ConfigData></Eeprom>)");
  Read r = read(text);
  EXPECT_EQ(r.d.esc.pdi_control, 0x3C00);  // the SII keeps word 0 as the file gives it
  EXPECT_TRUE(od::runs_firmware(r.d));
  EXPECT_TRUE(has_warning(r.warnings, line_of(text, "<ConfigData>"),
                          "PDI type 00h (PDI deactivated, word 0 #x3C00) in a device with mailbox SMs; the twin runs "
                          "its firmware as the mailbox needs, the SII keeps word 0"))
      << all(r.warnings);
  // A coupler (PDI type 0, no mailbox SM) has no firmware and nothing to warn about.
  const std::string coupler = esi("", R"(
        <Eeprom><ByteSize>2048</ByteSize><ConfigData>00010000</ConfigData></Eeprom>)");
  Read c = read(coupler);
  EXPECT_FALSE(od::runs_firmware(c.d));
  EXPECT_FALSE(warns_about(c.warnings, "PDI type")) << all(c.warnings);
}

TEST(TwinUserBrands, AnIghDumpWithUntypedSmsAndUnnamedPdos) {
  // Weidmueller UR20-FBC-EC from IgH's `ethercat xml`: Sm without text, PDO <Name></Name>.
  const std::string text = esi("", R"(
        <Sm Enable="1" StartAddress="#x1000" ControlByte="#x26" DefaultSize="512" />
        <Sm Enable="1" StartAddress="#x1400" ControlByte="#x22" DefaultSize="512" />
        <Sm Enable="0" StartAddress="#x1800" ControlByte="#x64" DefaultSize="0" />
        <Sm Enable="0" StartAddress="#x2400" ControlByte="#x20" DefaultSize="0" />
        <RxPdo Sm="2" Fixed="1" Mandatory="1">
          <Index>#x1600</Index>
          <Name></Name>
          <Entry><Index>#x7000</Index><SubIndex>1</SubIndex><BitLen>16</BitLen><Name></Name><DataType>UINT16</DataType></Entry>
        </RxPdo>
        <TxPdo Sm="3" Fixed="1" Mandatory="1">
          <Index>#x1a00</Index>
          <Name></Name>
          <Entry><Index>#x6000</Index><SubIndex>1</SubIndex><BitLen>32</BitLen><Name></Name><DataType>UINT32</DataType></Entry>
        </TxPdo>)");
  Read r = read(text);
  ASSERT_EQ(r.d.sync_managers.size(), 4u);
  EXPECT_EQ(r.d.sync_managers[0].type, od::SmType::MailboxOut);
  EXPECT_EQ(r.d.sync_managers[1].type, od::SmType::MailboxIn);
  EXPECT_EQ(r.d.sync_managers[2].type, od::SmType::Outputs);
  EXPECT_EQ(r.d.sync_managers[3].type, od::SmType::Inputs);
  EXPECT_TRUE(has_warning(r.warnings, line_of(text, "#x1000\" ControlByte"),
                          "no SM use given; taken as MBoxOut from ControlByte #x26"))
      << all(r.warnings);
  EXPECT_TRUE(has_warning(r.warnings, line_of(text, "#x2400\" ControlByte"),
                          "no SM use given; taken as Inputs from ControlByte #x20"))
      << all(r.warnings);
  EXPECT_TRUE(has_warning(r.warnings, line_of(text, "<RxPdo"),
                          "PDO 1600h has no Name; its mapping object is named 'PDO 1600h'"))
      << all(r.warnings);
  EXPECT_TRUE(has_warning(r.warnings, line_of(text, "<TxPdo"),
                          "PDO 1A00h has no Name; its mapping object is named 'PDO 1A00h'"))
      << all(r.warnings);
  auto back = load_device_string(write_device_xml(r.d), "twin.xml");
  ASSERT_TRUE(back) << back.error().to_string();
  ASSERT_NE(back->dictionary.find(0x1600), nullptr);
  EXPECT_EQ(back->dictionary.find(0x1600)->name, "PDO 1600h");
  EXPECT_EQ(back->dictionary.find(0x1A00)->name, "PDO 1A00h");
  // An Sm with text keeps it, and one with neither text nor ControlByte stays unused.
  Read plain = read(esi("", R"(<Sm DefaultSize="128" StartAddress="#x1000" ControlByte="#x26" Enable="1">MBoxOut</Sm><Sm/>)"));
  ASSERT_EQ(plain.d.sync_managers.size(), 2u);
  EXPECT_EQ(plain.d.sync_managers[1].type, od::SmType::Unused);
  EXPECT_FALSE(warns_about(plain.warnings, "SM use")) << all(plain.warnings);
}

}  // namespace
}  // namespace ecat::esi
