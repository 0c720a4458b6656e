// The twin import policy (docs/twins.md): an ESI written for this test in the
// shapes of issue 14's vendor files (byte-swapped 1C12h default, empty 1C13h,
// 1018h without data, 1C00h wrong, 1A00h with a stale SI0, PDO entries without
// objects, an SM with non-standard text, "#x0x" indices, STRING(0) with a
// default, a NaN REAL32). Each repair: the value the twin serves and the
// warning with its line; the twin loads as our device file; --strict fails.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "esi/device_loader.hpp"
#include "esi/esi_reader.hpp"
#include "esi/esi_writer_device_xml.hpp"
#include "esi/twin_import.hpp"
#include "twin_warnings.hpp"

namespace ecat::esi {
namespace {

using test::all;
using test::has_warning;

const char* const kEsi = R"(<?xml version="1.0"?>
<EtherCATInfo Version="1.2">
  <Vendor><Id>#x00000ABC</Id><Name>Twin Test</Name></Vendor>
  <Descriptions>
    <Groups><Group><Type>Drive</Type><Name>Drives</Name></Group></Groups>
    <Devices>
      <Device Physics="YY">
        <Type ProductCode="#x00001234" RevisionNo="#x00020001">TT-1</Type>
        <Name>TT-1 drive</Name>
        <GroupType>Drive</GroupType>
        <Profile>
          <ProfileNo>402</ProfileNo>
          <Dictionary>
            <DataTypes>
              <DataType><Name>USINT</Name><BitSize>8</BitSize></DataType>
              <DataType><Name>UINT</Name><BitSize>16</BitSize></DataType>
              <DataType><Name>UDINT</Name><BitSize>32</BitSize></DataType>
              <DataType><Name>REAL</Name><BitSize>32</BitSize></DataType>
              <DataType><Name>STRING(0)</Name><BitSize>0</BitSize></DataType>
              <DataType><Name>STRING(4)</Name><BitSize>32</BitSize></DataType>
              <DataType><Name>DT1018</Name><BitSize>144</BitSize>
                <SubItem><SubIdx>0</SubIdx><Name>Number of entries</Name><Type>USINT</Type><BitSize>8</BitSize><BitOffs>0</BitOffs><Flags><Access>ro</Access></Flags></SubItem>
                <SubItem><SubIdx>1</SubIdx><Name>Vendor ID</Name><Type>UDINT</Type><BitSize>32</BitSize><BitOffs>16</BitOffs><Flags><Access>ro</Access></Flags></SubItem>
                <SubItem><SubIdx>2</SubIdx><Name>Product code</Name><Type>UDINT</Type><BitSize>32</BitSize><BitOffs>48</BitOffs><Flags><Access>ro</Access></Flags></SubItem>
                <SubItem><SubIdx>3</SubIdx><Name>Revision</Name><Type>UDINT</Type><BitSize>32</BitSize><BitOffs>80</BitOffs><Flags><Access>ro</Access></Flags></SubItem>
                <SubItem><SubIdx>4</SubIdx><Name>Serial number</Name><Type>UDINT</Type><BitSize>32</BitSize><BitOffs>112</BitOffs><Flags><Access>ro</Access></Flags></SubItem>
              </DataType>
              <DataType><Name>DT1C00</Name><BitSize>48</BitSize>
                <SubItem><SubIdx>0</SubIdx><Name>SubIndex 000</Name><Type>USINT</Type><BitSize>8</BitSize><BitOffs>0</BitOffs><Flags><Access>ro</Access></Flags></SubItem>
                <SubItem><SubIdx>1</SubIdx><Name>SubIndex 001</Name><Type>USINT</Type><BitSize>8</BitSize><BitOffs>16</BitOffs><Flags><Access>ro</Access></Flags></SubItem>
                <SubItem><SubIdx>2</SubIdx><Name>SubIndex 002</Name><Type>USINT</Type><BitSize>8</BitSize><BitOffs>24</BitOffs><Flags><Access>ro</Access></Flags></SubItem>
                <SubItem><SubIdx>3</SubIdx><Name>SubIndex 003</Name><Type>USINT</Type><BitSize>8</BitSize><BitOffs>32</BitOffs><Flags><Access>ro</Access></Flags></SubItem>
                <SubItem><SubIdx>4</SubIdx><Name>SubIndex 004</Name><Type>USINT</Type><BitSize>8</BitSize><BitOffs>40</BitOffs><Flags><Access>ro</Access></Flags></SubItem>
              </DataType>
              <DataType><Name>DT1C12</Name><BitSize>48</BitSize>
                <SubItem><SubIdx>0</SubIdx><Name>SubIndex 000</Name><Type>USINT</Type><BitSize>8</BitSize><BitOffs>0</BitOffs><Flags><Access>rw</Access></Flags></SubItem>
                <SubItem><SubIdx>1</SubIdx><Name>SubIndex 001</Name><Type>UINT</Type><BitSize>16</BitSize><BitOffs>16</BitOffs><Flags><Access>rw</Access></Flags></SubItem>
                <SubItem><SubIdx>2</SubIdx><Name>SubIndex 002</Name><Type>UINT</Type><BitSize>16</BitSize><BitOffs>32</BitOffs><Flags><Access>rw</Access></Flags></SubItem>
              </DataType>
              <DataType><Name>DT1A00</Name><BitSize>80</BitSize>
                <SubItem><SubIdx>0</SubIdx><Name>SubIndex 000</Name><Type>USINT</Type><BitSize>8</BitSize><BitOffs>0</BitOffs><Flags><Access>ro</Access></Flags></SubItem>
                <SubItem><SubIdx>1</SubIdx><Name>SubIndex 001</Name><Type>UDINT</Type><BitSize>32</BitSize><BitOffs>16</BitOffs><Flags><Access>ro</Access></Flags></SubItem>
                <SubItem><SubIdx>2</SubIdx><Name>SubIndex 002</Name><Type>UDINT</Type><BitSize>32</BitSize><BitOffs>48</BitOffs><Flags><Access>ro</Access></Flags></SubItem>
              </DataType>
              <DataType><Name>DT2001</Name><BitSize>48</BitSize>
                <SubItem><SubIdx>0</SubIdx><Name>SubIndex 000</Name><Type>USINT</Type><BitSize>8</BitSize><BitOffs>0</BitOffs><Flags><Access>ro</Access></Flags></SubItem>
                <SubItem><Name>Reserved</Name><BitSize>8</BitSize><BitOffs>8</BitOffs></SubItem>
                <SubItem><SubIdx>1</SubIdx><Name>Limit</Name><Type>UINT</Type><BitSize>16</BitSize><BitOffs>16</BitOffs><Flags><Access>rw</Access></Flags></SubItem>
              </DataType>
            </DataTypes>
            <Objects>
              <Object><Index>#x1000</Index><Name>Device type</Name><Type>UDINT</Type><BitSize>32</BitSize><Info><DefaultData>92010200</DefaultData></Info><Flags><Access>ro</Access></Flags></Object>
              <Object><Index>#x1002</Index><Name>Manufacturer status</Name><Type>UDINT</Type><BitSize>32</BitSize><Info><DefaultData>00000000</DefaultData></Info><Flags><Access>ro</Access></Flags></Object>
              <Object><Index>#x1004</Index><Name>Number of PDOs</Name><Type>UDINT</Type><BitSize>32</BitSize><Info><DefaultData>01000100</DefaultData></Info><Flags><Access>ro</Access></Flags></Object>
              <Object><Index>#x1008</Index><Name>Device name</Name><Type>STRING(4)</Type><BitSize>32</BitSize><Info><DefaultString>TT-1</DefaultString></Info><Flags><Access>ro</Access></Flags></Object>
              <Object><Index>#x1009</Index><Name>Hardware version</Name><Type>STRING(0)</Type><BitSize>0</BitSize><Info><DefaultString>1.0</DefaultString></Info><Flags><Access>ro</Access></Flags></Object>
              <Object><Index>#x1018</Index><Name>Identity</Name><Type>DT1018</Type><BitSize>144</BitSize>
                <Info><SubItem><Name>Number of entries</Name><Info><DefaultData>04</DefaultData></Info></SubItem></Info>
                <Flags><Access>ro</Access></Flags></Object>
              <Object><Index>#x1A00</Index><Name>TxPDO 1</Name><Type>DT1A00</Type><BitSize>80</BitSize>
                <Info>
                  <SubItem><Name>SubIndex 000</Name><Info><DefaultData>02</DefaultData></Info></SubItem>
                  <SubItem><Name>SubIndex 001</Name><Info><DefaultData>10004160</DefaultData></Info></SubItem>
                  <SubItem><Name>SubIndex 002</Name><Info><DefaultData>00000000</DefaultData></Info></SubItem>
                </Info>
                <Flags><Access>ro</Access></Flags></Object>
              <Object><Index>#x1C00</Index><Name>SM type</Name><Type>DT1C00</Type><BitSize>48</BitSize>
                <Info>
                  <SubItem><Name>SubIndex 000</Name><Info><DefaultData>04</DefaultData></Info></SubItem>
                  <SubItem><Name>SubIndex 001</Name><Info><DefaultData>00</DefaultData></Info></SubItem>
                  <SubItem><Name>SubIndex 002</Name><Info><DefaultData>00</DefaultData></Info></SubItem>
                  <SubItem><Name>SubIndex 003</Name><Info><DefaultData>00</DefaultData></Info></SubItem>
                  <SubItem><Name>SubIndex 004</Name><Info><DefaultData>00</DefaultData></Info></SubItem>
                </Info>
                <Flags><Access>ro</Access></Flags></Object>
              <Object><Index>#x1C12</Index><Name>RxPDO assign</Name><Type>DT1C12</Type><BitSize>48</BitSize>
                <Info>
                  <SubItem><Name>SubIndex 000</Name><Info><DefaultData>01</DefaultData></Info></SubItem>
                  <SubItem><Name>SubIndex 001</Name><Info><DefaultData>1600</DefaultData></Info></SubItem>
                </Info>
                <Flags><Access>rw</Access></Flags></Object>
              <Object><Index>#x1C13</Index><Name>TxPDO assign</Name><Type>DT1C12</Type><BitSize>48</BitSize>
                <Info>
                  <SubItem><Name>SubIndex 000</Name><Info><DefaultData>00</DefaultData></Info></SubItem>
                </Info>
                <Flags><Access>rw</Access></Flags></Object>
              <Object><Index>#x6040</Index><Name>Controlword</Name><Type>UINT</Type><BitSize>16</BitSize><Info><DefaultData>0000</DefaultData></Info><Flags><Access>rw</Access><PdoMapping>R</PdoMapping></Flags></Object>
              <Object><Index>#x6041</Index><Name>Statusword</Name><Type>UINT</Type><BitSize>16</BitSize><Info><DefaultData>0000</DefaultData></Info><Flags><Access>ro</Access><PdoMapping>T</PdoMapping></Flags></Object>
              <Object><Index>#x2001</Index><Name>Limits</Name><Type>DT2001</Type><BitSize>48</BitSize>
                <Info><SubItem><Name>SubIndex 000</Name><Info><DefaultData>01</DefaultData></Info></SubItem>
                  <SubItem><Name>Limit</Name><Info><DefaultData>3412</DefaultData></Info></SubItem></Info>
                <Flags><Access>rw</Access></Flags></Object>
              <Object><Index>#x2000</Index><Name>Gain</Name><Type>REAL</Type><BitSize>32</BitSize><Info><DefaultData>0000C07F</DefaultData></Info><Flags><Access>rw</Access></Flags></Object>
            </Objects>
          </Dictionary>
        </Profile>
        <Fmmu>Outputs</Fmmu>
        <Fmmu>Inputs</Fmmu>
        <Sm DefaultSize="128" StartAddress="#x1000" ControlByte="#x26" Enable="1">MBoxOut</Sm>
        <Sm DefaultSize="128" StartAddress="#x1080" ControlByte="#x22" Enable="1">MBoxIn</Sm>
        <Sm StartAddress="#x1100" ControlByte="#x64" Enable="1">DriveIn</Sm>
        <Sm StartAddress="#x1180" ControlByte="#x20" Enable="1">Inputs</Sm>
        <RxPdo Fixed="1" Sm="2"><Index>#x1600</Index><Name>RxPDO 1</Name>
          <Entry><Index>#x6040</Index><SubIndex>0</SubIndex><BitLen>16</BitLen><Name>Controlword</Name><DataType>UINT</DataType></Entry>
        </RxPdo>
        <TxPdo Fixed="1" Sm="3"><Index>#x1A00</Index><Name>TxPDO 1</Name>
          <Entry><Index>#x0x6041</Index><SubIndex>0</SubIndex><BitLen>16</BitLen><Name>Statusword</Name><DataType>UINT</DataType></Entry>
          <Entry><Index>#x6000</Index><SubIndex>1</SubIndex><BitLen>8</BitLen><Name>Input 1</Name><DataType>USINT</DataType></Entry>
        </TxPdo>
        <Mailbox DataLinkLayer="true"><CoE SdoInfo="true" PdoAssign="true" PdoConfig="false" CompleteAccess="false"/></Mailbox>
      </Device>
    </Devices>
  </Descriptions>
</EtherCATInfo>
)";

int line_of(const std::string& needle) {
  const std::string text(kEsi);
  const auto at = text.find(needle);
  if (at == std::string::npos) return -1;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

std::uint64_t le(const od::Value& v) {
  std::uint64_t out = 0;
  for (std::size_t i = 0; i < v.size() && i < 8; ++i) out |= std::uint64_t{v[i]} << (8 * i);
  return out;
}

std::uint64_t value(const od::DeviceDescription& d, std::uint16_t index, std::uint8_t sub) {
  const od::Entry* e = d.dictionary.find(index, sub);
  EXPECT_NE(e, nullptr) << std::hex << index << ":" << int(sub);
  return e ? le(e->default_value) : ~0ull;
}

class TwinRepairs : public ::testing::Test {
 protected:
  void SetUp() override {
    auto r = read_esi_string(kEsi, "t.xml", {}, &warnings);
    ASSERT_TRUE(r) << r.error().to_string();
    d = *r;
  }
  std::vector<EsiWarning> warnings;
  od::DeviceDescription d;
};

TEST_F(TwinRepairs, IdentityFromTheSii) {
  EXPECT_EQ(value(d, 0x1018, 1), 0xABCu);
  EXPECT_EQ(value(d, 0x1018, 2), 0x1234u);
  EXPECT_EQ(value(d, 0x1018, 3), 0x20001u);
  EXPECT_EQ(value(d, 0x1018, 4), 0u);
  const int line = line_of("<Index>#x1018</Index>");
  EXPECT_TRUE(has_warning(warnings, line, "1018h:01 default #x00000000 differs from the SII vendor id #x00000ABC"))
      << all(warnings);
  EXPECT_TRUE(has_warning(warnings, line, "1018h:02")) << all(warnings);
  EXPECT_TRUE(has_warning(warnings, line, "1018h:03")) << all(warnings);
}

TEST_F(TwinRepairs, SmTypesFromTheSmElements) {
  // "DriveIn" with ControlByte 0x64 (buffered, written by the master) is Outputs.
  ASSERT_EQ(d.sync_managers.size(), 4u);
  EXPECT_EQ(d.sync_managers[2].type, od::SmType::Outputs);
  EXPECT_TRUE(has_warning(warnings, line_of(">DriveIn<"), "unknown SM use 'DriveIn'; taken as Outputs from ControlByte #x64"))
      << all(warnings);
  for (std::uint8_t sub = 1; sub <= 4; ++sub) EXPECT_EQ(value(d, 0x1C00, sub), sub);
  EXPECT_TRUE(has_warning(warnings, line_of("<Index>#x1C00</Index>"), "1C00h:03 default #x00 differs")) << all(warnings);
}

TEST_F(TwinRepairs, AssignmentFromThePdosWithSm) {
  // 1C12h:01 written "1600" (= 0x0016, byte-swapped): the RxPdo with Sm="2" says 1600h.
  EXPECT_EQ(value(d, 0x1C12, 0), 1u);
  EXPECT_EQ(value(d, 0x1C12, 1), 0x1600u);
  EXPECT_TRUE(has_warning(warnings, line_of("<Index>#x1C12</Index>"),
                          "1C12h default (SI0 1 0x0016) differs from the PDOs with Sm=\"2\" (SI0 1 0x1600)"))
      << all(warnings);
  // 1C13h SI0 = 0 while the TxPdo carries Sm="3": the object grows its entry.
  EXPECT_EQ(value(d, 0x1C13, 0), 1u);
  EXPECT_EQ(value(d, 0x1C13, 1), 0x1A00u);
  EXPECT_TRUE(has_warning(warnings, line_of("<Index>#x1C13</Index>"), "(SI0 0) differs")) << all(warnings);
}

TEST_F(TwinRepairs, MappingFromTheSiiEntries) {
  // "#x0x6041" read as 6041h, with a warning on its Entry.
  EXPECT_TRUE(has_warning(warnings, line_of("#x0x6041"), "two hex prefixes")) << all(warnings);
  ASSERT_EQ(d.tx_pdos.size(), 1u);
  EXPECT_EQ(d.tx_pdos[0].entries[0].index, 0x6041);
  // 1A00h's dictionary said SI0 2 with a zero entry: the SII's two entries win.
  EXPECT_EQ(value(d, 0x1A00, 0), 2u);
  EXPECT_EQ(value(d, 0x1A00, 1), 0x60410010u);
  EXPECT_EQ(value(d, 0x1A00, 2), 0x60000108u);
  EXPECT_TRUE(has_warning(warnings, line_of("<Index>#x1A00</Index><Name>TxPDO 1</Name><Type>"), "1A00h default"))
      << all(warnings);
  // 6000h:01 exists only as a PDO entry: a process-data object is created.
  const od::Entry* e = d.dictionary.find(0x6000, 1);
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->bit_length, 8);
  EXPECT_TRUE(e->access.tx_mappable());
  EXPECT_TRUE(has_warning(warnings, line_of("<TxPdo"), "6000h has no dictionary object; object created")) << all(warnings);
}

TEST_F(TwinRepairs, ValuesThatRoundTrip) {
  // STRING(0) with default "1.0": the entry is made 3 bytes.
  const od::Entry* hw = d.dictionary.find(0x1009, 0);
  ASSERT_NE(hw, nullptr);
  EXPECT_EQ(hw->bit_length, 24);
  EXPECT_TRUE(has_warning(warnings, line_of("<DefaultString>1.0"), "longer than the declared 0 bytes")) << all(warnings);
  // The NaN REAL32 is written as its bit pattern and read back to the same bytes.
  const std::string xml = write_device_xml(d);
  EXPECT_NE(xml.find("default=\"#x7FC00000\""), std::string::npos);
  auto back = load_device_string(xml, "twin.xml");
  ASSERT_TRUE(back) << back.error().to_string();
  EXPECT_EQ(back->dictionary.find(0x2000, 0)->default_value, (od::Value{0x00, 0x00, 0xC0, 0x7F}));
  EXPECT_EQ(le(back->dictionary.find(0x1C12, 1)->default_value), 0x1600u);
  EXPECT_EQ(le(back->dictionary.find(0x1018, 1)->default_value), 0xABCu);
  // A SubItem without a Type is padding: the record keeps its other entries.
  ASSERT_NE(back->dictionary.find(0x2001, 1), nullptr);
  EXPECT_EQ(le(back->dictionary.find(0x2001, 1)->default_value), 0x1234u);
  EXPECT_TRUE(has_warning(warnings, line_of("<Name>Reserved</Name>"), "has no Type; taken as 8 bits of padding"))
      << all(warnings);
  // CiA 301 objects with the types of older devices load as written.
  EXPECT_EQ(back->dictionary.find(0x1004, 0)->type, od::DataType::Unsigned32);
  EXPECT_EQ(le(back->dictionary.find(0x1004, 0)->default_value), 0x00010001u);
  EXPECT_EQ(back->dictionary.find(0x1002, 0)->type, od::DataType::Unsigned32);
  EXPECT_EQ(back->dictionary.find(0x1008, 0)->bit_length, 32);
}

class TwinImport : public ::testing::Test {
 protected:
  void SetUp() override {
    path = ::testing::TempDir() + "twin_import_test.xml";
    std::ofstream(path) << kEsi;
  }
  std::string path;
};

TEST_F(TwinImport, TheTwinIsTheLoadedDeviceFile) {
  std::vector<EsiWarning> w;
  auto twin = import_twin(path, {}, &w);
  ASSERT_TRUE(twin) << twin.error().to_string();
  EXPECT_FALSE(w.empty());
  EXPECT_EQ(le(twin->dictionary.find(0x1C13, 1)->default_value), 0x1A00u);
  EXPECT_EQ(twin->source_file, path);
}

TEST_F(TwinImport, StrictMakesTheFirstWarningAnError) {
  std::vector<EsiWarning> w;
  auto twin = import_twin(path, {{}, true}, &w);
  ASSERT_FALSE(twin);
  ASSERT_FALSE(w.empty());
  EXPECT_EQ(twin.error().line, w.front().line);
  EXPECT_NE(twin.error().to_string().find("(--strict: import warnings are errors)"), std::string::npos);
  EXPECT_EQ(twin.error().file, path);
}

}  // namespace
}  // namespace ecat::esi
