// Positions in one-line vendor files (issue 32 item 2): configurator exports
// (acontis EniEngine ENIs, some ESIs) are written on one line, so a bare
// "file:1" names nothing. An element that is not the first to start on its
// line is given as "file:line:column", the 1-based byte column of its '<'
// (docs/twins.md "Positions in vendor files"); the first element of a line
// keeps "file:line", so pretty-printed files read as before.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "esi/eni_devices.hpp"
#include "esi/eni_reader.hpp"
#include "esi/esi_reader.hpp"
#include "esi/xml_lines.hpp"

namespace ecat::esi {
namespace {

std::vector<std::string> texts(const std::vector<EsiWarning>& ws, const char* file) {
  std::vector<std::string> out;
  for (const auto& w : ws) out.push_back(w.to_string(file));
  return out;
}

// 1-based column of the n-th (from 0) occurrence of `what` in `text`.
int column_of(const std::string& text, const std::string& what, int n = 0) {
  std::size_t at = text.find(what);
  while (n-- > 0) at = text.find(what, at + 1);
  return static_cast<int>(at) + 1;
}

TEST(OneLinePositions, LineIndexGivesTheColumnOnlyAfterTheFirstElementOfALine) {
  const std::string text = "<?xml version=\"1.0\"?><A>\n  <B><C/></B>\n<D/>text <E/>\n";
  const LineIndex lines(text);
  EXPECT_EQ(lines.position_of(static_cast<std::ptrdiff_t>(text.find("<A>"))).to_string(), "1");
  EXPECT_EQ(lines.position_of(static_cast<std::ptrdiff_t>(text.find("<B>"))).to_string(), "2");
  EXPECT_EQ(lines.position_of(static_cast<std::ptrdiff_t>(text.find("<C/>"))).to_string(), "2:6");
  EXPECT_EQ(lines.position_of(static_cast<std::ptrdiff_t>(text.find("<D/>"))).to_string(), "3");
  EXPECT_EQ(lines.position_of(static_cast<std::ptrdiff_t>(text.find("<E/>"))).to_string(), "3:10");
  EXPECT_EQ(lines.position_of(-1).to_string(), "0");
}

// An ESI as a configurator writes it: everything on line 1.
const std::string kOneLineEsi =
    "<?xml version=\"1.0\"?><EtherCATInfo><Vendor><Id>#x1337</Id><Name>rt-labs AB</Name></Vendor>"
    "<Descriptions><Groups><Group><Type>G</Type><Name>G</Name></Group></Groups><Devices><Device Physics=\"YY\">"
    "<Type ProductCode=\"#x12783456\" RevisionNo=\"#x00000001\">One line</Type><Name>One line</Name>"
    "<GroupType>G</GroupType><Fmmu>Outputs</Fmmu><Fmmu>Inputs</Fmmu>"
    "<Sm DefaultSize=\"128\" StartAddress=\"#x1000\" ControlByte=\"#x26\" Enable=\"1\">MBoxOut</Sm>"
    "<Sm DefaultSize=\"128\" StartAddress=\"#x1080\" ControlByte=\"#x22\" Enable=\"1\">MBoxIn</Sm>"
    "<Sm StartAddress=\"#x1100\" ControlByte=\"#x24\" Enable=\"1\">Outputs</Sm>"
    "<Sm StartAddress=\"#x1180\" ControlByte=\"#x20\" Enable=\"1\">Inputs</Sm>"
    "<TxPdo Fixed=\"1\" Sm=\"3\"><Index>#x1A00</Index><Name>In</Name>"
    "<Entry><Index>#x0x6000</Index><SubIndex>1</SubIndex><BitLen>8</BitLen><Name>Byte</Name><DataType>USINT</DataType></Entry>"
    "</TxPdo><Mailbox DataLinkLayer=\"1\"><CoE SdoInfo=\"1\" PdoUpload=\"1\"/></Mailbox>"
    "<Eeprom><ByteSize>2048</ByteSize><ConfigData>050E0306102700</ConfigData></Eeprom></Device></Devices>"
    "</Descriptions></EtherCATInfo>";

TEST(OneLinePositions, EsiWarningsOfAOneLineFileCarryTheirColumn) {
  std::vector<EsiWarning> warnings;
  auto d = read_esi_string(kOneLineEsi, "one.xml", EsiSelection{}, &warnings);
  ASSERT_TRUE(d) << d.error().to_string();
  const std::vector<std::string> got = texts(warnings, "one.xml");
  // The Entry (the double hex prefix of its Index) is named by its column,
  // and so is the TxPdo by the repair made later on the dictionary model (the
  // object the entry maps is created): od's source positions carry the
  // column too (docs/twins.md "Positions in vendor files").
  ASSERT_EQ(column_of(kOneLineEsi, "<Entry>"), 715);
  ASSERT_EQ(column_of(kOneLineEsi, "<TxPdo"), 655);
  const std::vector<std::string> expected{
      "one.xml:1:715: warning: Entry: Index '#x0x6000' has two hex prefixes; read as #x6000",
      "one.xml:1:655: warning: TxPdo: 6000h has no dictionary object; object created as process data: "
      "subindex 01 (8 bits)",
  };
  for (const auto& e : expected) {
    EXPECT_NE(std::find(got.begin(), got.end(), e), got.end()) << e << "\nin\n" << ::testing::PrintToString(got);
  }
  for (const auto& w : warnings) EXPECT_GT(w.line.column, 0) << w.to_string("one.xml");
}

TEST(OneLinePositions, EsiParseErrorOfAOneLineFileCarriesItsColumn) {
  // A parse error in the middle of the line: its column (pugixml points two
  // bytes into the mismatched end tag at 903), not just line 1.
  std::string broken = kOneLineEsi;
  broken.replace(broken.find("</Mailbox>"), 10, "</Mailbx>");
  auto p = read_esi_string(broken, "one.xml", EsiSelection{}, nullptr);
  ASSERT_FALSE(p);
  EXPECT_EQ(p.error().to_string(), "one.xml:1:905: XML parse error: Start-end tags mismatch");
}

// An ENI as acontis' EniEngine writes it: one line.
std::string one_line_eni(const std::string& process_data, const std::string& mailbox_rest = "") {
  return "<?xml version=\"1.0\" encoding=\"utf-8\"?><EtherCATConfig Version=\"1.3\"><Config><Slave><Info>"
         "<Name>Drive</Name><VendorId>154</VendorId><ProductCode>199460</ProductCode><RevisionNo>66592</RevisionNo>"
         "</Info>" + process_data +
         "<Mailbox><Send><Start>4096</Start><Length>140</Length></Send><Recv><Start>4236</Start><Length>140</Length>"
         "</Recv><Protocol>CoE</Protocol><Protocol>EoE</Protocol><Protocol>XoE</Protocol>" + mailbox_rest +
         "</Mailbox></Slave></Config></EtherCATConfig>";
}

TEST(OneLinePositions, EniWarningsAndErrorsOfAOneLineFileCarryTheirColumn) {
  const std::string xml = one_line_eni("");
  std::vector<EsiWarning> warnings;
  auto net = read_eni_string(xml, "net.xml", &warnings);
  ASSERT_TRUE(net) << net.error().to_string();
  EXPECT_EQ(texts(warnings, "net.xml"),
            (std::vector<std::string>{"net.xml:1:" + std::to_string(column_of(xml, "<Protocol>XoE")) +
                                      ": warning: Protocol: mailbox protocol 'XoE' unknown; ignored"}));
  EXPECT_EQ(net->slaves[0].line.to_string(), std::to_string(column_of(xml, "<Slave>")).insert(0, "1:"));

  const std::string bad = one_line_eni("<ProcessData><Sm2><Type>Both</Type></Sm2></ProcessData>");
  auto r = read_eni_string(bad, "net.xml");
  ASSERT_FALSE(r);
  ASSERT_EQ(column_of(bad, "<Type>Both"), 220);
  EXPECT_EQ(r.error().to_string(), "net.xml:1:220: Sm2: Type 'Both' is neither Outputs nor Inputs");
}

// The synthesised device of a one-line ENI: the warning at the Entry that maps
// an object the ENI does not describe, and a refusal of the layout, each at
// its column (before: "net.xml:1").
TEST(OneLinePositions, EniDevicesOfAOneLineFileNameTheirElementsByColumn) {
  const std::string pd =
      "<ProcessData><Sm2><Type>Outputs</Type><Pdo>#x1600</Pdo></Sm2><Sm3><Type>Inputs</Type><Pdo>#x1A22</Pdo></Sm3>"
      "<RxPdo><Index>#x1600</Index><Entry><Index>#x6040</Index><SubIndex>0</SubIndex><BitLen>16</BitLen>"
      "<DataType>UINT</DataType></Entry></RxPdo><TxPdo><Index>#x1A22</Index>"
      "<Entry><Index>#x6041</Index><SubIndex>0</SubIndex><BitLen>16</BitLen><DataType>UINT</DataType></Entry>"
      "<Entry><Index>#x1002</Index><SubIndex>0</SubIndex><BitLen>32</BitLen><DataType>UDINT</DataType></Entry>"
      "</TxPdo></ProcessData>";
  const std::string xml = one_line_eni(pd);
  auto net = read_eni_string(xml, "net.xml");
  ASSERT_TRUE(net) << net.error().to_string();
  std::vector<EsiWarning> warnings;
  auto devs = eni_devices(*net, {}, &warnings);
  ASSERT_TRUE(devs) << devs.error().to_string();
  const std::string entry = "net.xml:1:" + std::to_string(column_of(xml, "<Entry><Index>#x1002")) +
                            ": warning: Entry: PDO #x1A22 maps 1002h:00, an object of the communication area the "
                            "ENI does not describe; object created as process data (32 bits)";
  const std::vector<std::string> got = texts(warnings, "net.xml");
  EXPECT_NE(std::find(got.begin(), got.end(), entry), got.end()) << ::testing::PrintToString(got);

  // Sm2 placed where its three buffers run into Sm3: refused at Sm3's column.
  const std::string clash = one_line_eni(
      "<ProcessData><Sm2><Type>Outputs</Type><StartAddress>#x1100</StartAddress><Pdo>#x1600</Pdo></Sm2>"
      "<Sm3><Type>Inputs</Type><StartAddress>#x1102</StartAddress><Pdo>#x1A00</Pdo></Sm3>"
      "<RxPdo><Index>#x1600</Index><Entry><Index>#x6040</Index><SubIndex>0</SubIndex><BitLen>16</BitLen>"
      "<DataType>UINT</DataType></Entry></RxPdo><TxPdo><Index>#x1A00</Index>"
      "<Entry><Index>#x6041</Index><SubIndex>0</SubIndex><BitLen>16</BitLen><DataType>UINT</DataType></Entry>"
      "</TxPdo></ProcessData>");
  auto cnet = read_eni_string(clash, "net.xml");
  ASSERT_TRUE(cnet) << cnet.error().to_string();
  auto cdevs = eni_devices(*cnet, {});
  ASSERT_FALSE(cdevs);
  EXPECT_EQ(cdevs.error().to_string().rfind("net.xml:1:", 0), 0u) << cdevs.error().to_string();
  EXPECT_NE(cdevs.error().line.column, 0) << cdevs.error().to_string();
}

// ENI EoE InitCmds (issue 31 item 1): the Set IP Parameter request with its
// EoE header and without, decoded field by field; bad Data is an error at
// its column.
TEST(OneLinePositions, EniEoeInitCmdsAreReadAsSetIpParameterRequests) {
  // Header 02 01 00 00 (type 2, last fragment); flags 1Fh: MAC, IP, subnet,
  // gateway, DNS server.
  const std::string with_header =
      "<EoE><InitCmds><InitCmd><Transition>PS</Transition><Comment>set ip</Comment><Timeout>1000</Timeout>"
      "<Data>020100001f00000000010529a1b2140aa8c000ffffff010aa8c008080808</Data></InitCmd>"
      // Body alone; flags 22h: IP and DNS name ("drive1", NUL padded to 32 bytes).
      "<InitCmd><Transition>IP</Transition><Data>22000000150aa8c0"
      "6472697665310000000000000000000000000000000000000000000000000000</Data></InitCmd>"
      "<InitCmd><Transition>PS</Transition><Data>0200000002000000</Data><Disabled>true</Disabled></InitCmd>"
      "</InitCmds></EoE>";
  const std::string xml = one_line_eni("", with_header);
  std::vector<EsiWarning> warnings;
  auto net = read_eni_string(xml, "net.xml", &warnings);
  ASSERT_TRUE(net) << net.error().to_string();
  const auto& cmds = net->slaves[0].eoe_init_cmds;
  ASSERT_EQ(cmds.size(), 2u);  // the disabled one is not sent
  EXPECT_TRUE(cmds[0].set_ip);
  EXPECT_EQ(cmds[0].transitions, (std::vector<std::string>{"PS"}));
  EXPECT_EQ(cmds[0].comment, "set ip");
  EXPECT_EQ(cmds[0].line.to_string(), "1:" + std::to_string(column_of(xml, "<InitCmd>")));
  EXPECT_EQ(cmds[0].ip.flags, 0x1Fu);
  EXPECT_EQ(cmds[0].ip.mac, (std::array<std::uint8_t, 6>{0x00, 0x01, 0x05, 0x29, 0xA1, 0xB2}));
  EXPECT_EQ(cmds[0].ip.ip, 0xC0A80A14u);
  EXPECT_EQ(cmds[0].ip.subnet, 0xFFFFFF00u);
  EXPECT_EQ(cmds[0].ip.gateway, 0xC0A80A01u);
  EXPECT_EQ(cmds[0].ip.dns_server, 0x08080808u);
  EXPECT_EQ(cmds[0].data.size(), 4u + 4 + 6 + 16);
  EXPECT_EQ(cmds[1].transitions, (std::vector<std::string>{"IP"}));
  EXPECT_EQ(cmds[1].ip.flags, 0x22u);
  EXPECT_EQ(cmds[1].ip.ip, 0xC0A80A15u);
  EXPECT_EQ(cmds[1].ip.dns_name, "drive1");
  // Nothing about EoE InitCmds is ignored any more; only the unknown protocol warns.
  EXPECT_EQ(texts(warnings, "net.xml"),
            (std::vector<std::string>{"net.xml:1:" + std::to_string(column_of(xml, "<Protocol>XoE")) +
                                      ": warning: Protocol: mailbox protocol 'XoE' unknown; ignored"}));

  // 5 bytes: neither a body (flags 02h need 8) nor a header and a body.
  const std::string short_data = one_line_eni(
      "", "<EoE><InitCmds><InitCmd><Transition>PS</Transition><Data>0200000002</Data></InitCmd></InitCmds></EoE>");
  auto bad = read_eni_string(short_data, "net.xml");
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().to_string(),
            "net.xml:1:" + std::to_string(column_of(short_data, "<Data>0200000002")) +
                ": EoE InitCmd Data of 5 bytes is no Set IP Parameter request (UINT32 flags, then the flagged "
                "fields, with or without the 4-byte EoE header of frame type 2)");

  // A Set Address Filter request (type 4) is passed on, not checked; an
  // InitCmd of another transition than IP/PS/SO is not checked either.
  const std::string other = one_line_eni(
      "", "<EoE><InitCmds><InitCmd><Transition>PS</Transition><Data>040100000100ffffffffffff</Data></InitCmd>"
          "<InitCmd><Transition>OS</Transition><Data>02000000020aa8c0</Data></InitCmd></InitCmds></EoE>");
  std::vector<EsiWarning> ow;
  auto onet = read_eni_string(other, "net.xml", &ow);
  ASSERT_TRUE(onet) << onet.error().to_string();
  ASSERT_EQ(onet->slaves[0].eoe_init_cmds.size(), 2u);
  EXPECT_FALSE(onet->slaves[0].eoe_init_cmds[0].set_ip);
  const std::string first = std::to_string(column_of(other, "<InitCmd>"));
  const std::string second = std::to_string(column_of(other, "<InitCmd>", 1));
  EXPECT_EQ(texts(ow, "net.xml"),
            (std::vector<std::string>{
                "net.xml:1:" + std::to_string(column_of(other, "<Protocol>XoE")) +
                    ": warning: Protocol: mailbox protocol 'XoE' unknown; ignored",
                "net.xml:1:" + first + ": warning: InitCmd: EoE InitCmd of frame type 4 (not a Set IP Parameter "
                                       "request, type 2): answered by the slave when the master sends it, not checked",
                "net.xml:1:" + second + ": warning: InitCmd: EoE InitCmd on transition OS: the virtual slave checks "
                                        "those of IP, PS and SO only (the master sends them before SafeOp or Op); "
                                        "not checked there"}));
}

}  // namespace
}  // namespace ecat::esi
