// ETG.2100 ENI reader: what it takes from SOEM's sample ENI, and its errors
// with file:line; the synthesised device of a slave without ESI.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "esi/eni_devices.hpp"
#include "esi/eni_reader.hpp"

namespace ecat::esi {
namespace {

std::string data(const char* name) { return std::string(ECAT_SOURCE_DIR) + "/tests/data/eni/" + name; }

std::string error_of(const std::string& xml) {
  auto r = read_eni_string(xml, "net.xml");
  return r ? std::string("no error") : r.error().to_string();
}

// One slave; `info` and `rest` replace its parts. Line 1 is <EtherCATConfig>.
std::string one_slave(const std::string& info, const std::string& rest = "") {
  return "<EtherCATConfig>\n<Config>\n<Slave>\n<Info>\n" + info + "</Info>\n" + rest + "</Slave>\n</Config>\n</EtherCATConfig>\n";
}

const std::string kIdentity = "<VendorId>2</VendorId>\n<ProductCode>#x0bb83052</ProductCode>\n<RevisionNo>0x100000</RevisionNo>\n";

TEST(EniReader, SoemSampleSlavesMailboxesAndInitCmds) {
  std::vector<EsiWarning> warnings;
  auto net = read_eni(data("soem-sample-eni.xml"), &warnings);
  ASSERT_TRUE(net) << net.error().to_string();
  EXPECT_TRUE(warnings.empty());
  ASSERT_EQ(net->slaves.size(), 2u);
  const EniSlave& a = net->slaves[0];
  EXPECT_EQ(a.name, "Sample device A");
  EXPECT_EQ(a.vendor_id, 1u);
  EXPECT_EQ(a.product_code, 0x1234u);
  EXPECT_EQ(a.revision, 0u);
  EXPECT_FALSE(a.phys_addr.has_value());
  ASSERT_TRUE(a.mailbox.has_value());
  EXPECT_EQ(a.mailbox->out_start, 0x1000);
  EXPECT_EQ(a.mailbox->out_length, 128);
  EXPECT_EQ(a.mailbox->in_start, 0x1100);  // written as <Receive>
  EXPECT_TRUE(a.mailbox->coe);
  ASSERT_EQ(a.coe_init_cmds.size(), 4u);
  EXPECT_EQ(a.coe_init_cmds[1].index, 0x1C13);
  EXPECT_EQ(a.coe_init_cmds[1].subindex, 1);
  EXPECT_EQ(a.coe_init_cmds[1].data, (od::Value{0x02, 0x1A}));
  EXPECT_EQ(a.coe_init_cmds[1].transitions, (std::vector<std::string>{"PS"}));
  EXPECT_EQ(a.coe_init_cmds[1].line, 41);
  const EniCoeInitCmd& ca = net->slaves[1].coe_init_cmds.at(0);
  EXPECT_TRUE(ca.complete_access);
  EXPECT_EQ(ca.data, (od::Value{0x03, 0x00, 0x01, 0x16, 0x07, 0x16, 0x1C, 0x16}));
  EXPECT_TRUE(net->cyclic.empty());
}

TEST(EniReader, ErrorsNameFileAndLine) {
  EXPECT_EQ(error_of("<EtherCATInfo/>"), "net.xml: not an ENI file: no EtherCATConfig root element");
  EXPECT_EQ(error_of("<EtherCATConfig>\n<Config>\n</Config>\n</EtherCATConfig>"), "net.xml:2: Config lists no Slave");
  EXPECT_EQ(error_of(one_slave("<VendorId>2</VendorId>\n<RevisionNo>1</RevisionNo>\n")),
            "net.xml:4: Info: ProductCode missing");
  EXPECT_EQ(error_of(one_slave("<VendorId>2</VendorId>\n<ProductCode>x12</ProductCode>\n<RevisionNo>1</RevisionNo>\n")),
            "net.xml:6: ProductCode: 'x12' is not a number that fits 32 bits");
  EXPECT_EQ(error_of(one_slave(kIdentity, "<ProcessData>\n<Sm2>\n<Type>Both</Type>\n</Sm2>\n</ProcessData>\n")),
            "net.xml:11: Sm2: Type 'Both' is neither Outputs nor Inputs");
  const std::string mbx = "<Mailbox>\n<Send><Start>4096</Start><Length>128</Length></Send>\n"
                          "<Recv><Start>4224</Start><Length>128</Length></Recv>\n<CoE><InitCmds>\n";
  EXPECT_EQ(error_of(one_slave(kIdentity, mbx + "<InitCmd><Transition>PS</Transition><Ccs>2</Ccs><Index>#x8000</Index>"
                                                "<SubIndex>1</SubIndex>\n<Data>0g</Data></InitCmd>\n</InitCmds></CoE>\n</Mailbox>\n")),
            "net.xml:14: Data: '0g' is not hex binary (two hex digits per byte)");
  EXPECT_EQ(error_of(one_slave(kIdentity, mbx + "<InitCmd><Transition>PS</Transition><Ccs>3</Ccs><Index>#x8000</Index>"
                                                "<SubIndex>1</SubIndex><Data>00</Data></InitCmd>\n</InitCmds></CoE>\n</Mailbox>\n")),
            "net.xml:13:37: Ccs 3 is neither 1 nor 2");  // <Ccs> after <InitCmd><Transition>..: its column
  EXPECT_EQ(error_of(one_slave(kIdentity, mbx + "<InitCmd><Ccs>2</Ccs><Index>#x8000</Index><SubIndex>1</SubIndex>"
                                                "<Data>00</Data></InitCmd>\n</InitCmds></CoE>\n</Mailbox>\n")),
            "net.xml:13: InitCmd without Transition");
  EXPECT_EQ(error_of(one_slave(kIdentity, "<ProcessData>\n<RxPdo>\n<Index>#x1A00</Index>\n</RxPdo>\n</ProcessData>\n")),
            "net.xml:11: RxPdo index #x1A00 outside #x1600..#x17FF");
  EXPECT_EQ(error_of("<EtherCATConfig>\n<Config>\n<Slave>\n</Slave"), "net.xml:4: XML parse error: Error parsing end element tag");
}

TEST(EniDevices, SampleWithoutEsiIsSynthesisedWithWarnings) {
  auto net = read_eni(data("soem-sample-eni.xml"));
  ASSERT_TRUE(net);
  std::vector<EsiWarning> warnings;
  auto devs = eni_devices(*net, {}, &warnings);
  ASSERT_TRUE(devs) << devs.error().to_string();
  ASSERT_EQ(devs->size(), 2u);
  const od::DeviceDescription& a = (*devs)[0].device;
  EXPECT_EQ((*devs)[0].esi_file, "");
  EXPECT_EQ(a.identity.vendor_id, 1u);
  EXPECT_EQ(a.identity.product_code, 0x1234u);
  EXPECT_EQ(a.identity.name, "Sample device A");
  ASSERT_GE(a.sync_managers.size(), 4u);
  EXPECT_EQ(a.sync_managers[0].type, od::SmType::MailboxOut);
  EXPECT_EQ(a.sync_managers[1].start_address, 0x1100);
  EXPECT_EQ(a.sync_managers[3].type, od::SmType::Inputs);
  ASSERT_EQ(a.tx_pdos.size(), 2u);
  EXPECT_EQ(a.tx_pdos[0].index, 0x1A02);
  EXPECT_TRUE(a.tx_pdos[0].entries.empty());
  ASSERT_NE(a.dictionary.find(0x1C13), nullptr);
  EXPECT_EQ((*devs)[1].device.rx_pdos.size(), 3u);
  ASSERT_EQ(warnings.size(), 5u);
  EXPECT_EQ(warnings[0].to_string("n"), "n:41: warning: Pdo: PDO #x1A02 is assigned but the ENI does not describe "
                                        "its entries; it is made with none");
  EXPECT_EQ(warnings[4].line, 93);
}

TEST(EniDevices, ASynthesisErrorPointsAtTheEniLine) {
  // A PDO entry 8 bits wide on an object a CoE InitCmd writes with 2 bytes.
  const std::string xml = one_slave(
      kIdentity,
      "<ProcessData>\n<Sm3><Type>Inputs</Type><Pdo>#x1A00</Pdo></Sm3>\n"
      "<TxPdo><Index>#x1A00</Index><Entry><Index>#x6000</Index><SubIndex>0</SubIndex><BitLen>8</BitLen></Entry>\n"
      "<Entry><Index>#x6000</Index><SubIndex>1</SubIndex><BitLen>8</BitLen></Entry></TxPdo>\n</ProcessData>\n");
  auto net = read_eni_string(xml, "net.xml");
  ASSERT_TRUE(net) << net.error().to_string();
  auto devs = eni_devices(*net, {});
  ASSERT_FALSE(devs);
  EXPECT_EQ(devs.error().to_string(),
            "net.xml:11:29: slave 1: #x6000 is used both as a variable (subindex 0) and with subindices");
}

// Bad input never crashes: every prefix of both test ENIs is read (and, if it
// reads, made into devices) with an error or a result.
TEST(EniReader, EveryPrefixGivesAResultOrAnError) {
  for (const char* name : {"soem-sample-eni.xml", "servo-and-io.xml"}) {
    std::ifstream in(data(name), std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    const std::string xml = text.str();
    ASSERT_FALSE(xml.empty()) << name;
    int read = 0;
    for (std::size_t n = 0; n < xml.size(); n += 7) {
      std::vector<EsiWarning> w;
      auto net = read_eni_string(std::string_view(xml).substr(0, n), "cut.xml", &w);
      if (!net) {
        EXPECT_FALSE(net.error().message.empty());
        continue;
      }
      ++read;
      (void)eni_devices(*net, {}, &w);
    }
    EXPECT_EQ(read, 0) << name << ": a cut file read as complete";
  }
}

}  // namespace
}  // namespace ecat::esi
