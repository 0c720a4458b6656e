// Corpus files that were known limits of the twin chain (tests/twins/
// known-limits.txt), each imported from the vendor file itself and checked
// the way a master sees it: the SDO upload bytes of the objects the repair
// touched, the import warning with its file:line, and the start-up to Op.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "esi/device_loader.hpp"
#include "esi/esi_writer_device_xml.hpp"
#include "esi/twin_import.hpp"
#include "inprocess_fixture.hpp"
#include "master/coe_client.hpp"

namespace ecat::test {
namespace {

std::string corpus(const std::string& file) { return std::string(ECAT_SOURCE_DIR) + "/tests/data/esi-vendor/" + file; }

struct Twin {
  od::DeviceDescription device;
  std::vector<esi::EsiWarning> warnings;
};

Twin import(const std::string& file, std::uint32_t product, std::uint32_t revision) {
  Twin t;
  esi::TwinImportOptions o;
  o.selection.product_code = product;
  o.selection.revision = revision;
  auto d = esi::import_twin(corpus(file), o, &t.warnings);
  EXPECT_TRUE(d) << d.error().to_string();
  if (d) t.device = *d;
  return t;
}

bool has_warning(const Twin& t, int line, const std::string& text) {
  return std::any_of(t.warnings.begin(), t.warnings.end(),
                     [&](const esi::EsiWarning& w) { return w.line == line && w.message == text; });
}

std::string all(const Twin& t) {
  std::string s;
  for (const auto& w : t.warnings) s += w.to_string("f") + "\n";
  return s;
}

using Bytes8 = std::vector<std::uint8_t>;

// Elmo Gold (elmo-gold-ecat.xml, Boot revision 1): DT1600 types sub 3
// "Controlword" as UINT. The twin's 1600h:03 is UNSIGNED32 and holds the SII's
// mapping 6040h:00, 16 bits; the master reads 1600h whole and reaches Op.
TEST(TwinLimitsElmo, MappingEntriesTypedAsTheMappedObjectAreUnsigned32) {
  Twin t = import("elmo-gold-ecat.xml", 0x00030924, 0x00000001);
  EXPECT_TRUE(has_warning(t, 163,
                          "1600h (PDO mapping) entries 03 (UNSIGNED16, 16 bits) are typed as the objects they map; "
                          "a mapping entry is UNSIGNED32, so are the twin's"))
      << all(t);
  EXPECT_TRUE(has_warning(t, 270,
                          "1A00h (PDO mapping) entries 03 (UNSIGNED16, 16 bits) are typed as the objects they map; "
                          "a mapping entry is UNSIGNED32, so are the twin's"))
      << all(t);
  EXPECT_TRUE(has_warning(t, 422, "60FEh:00 has no default; the twin's reads 2, the highest subindex (CiA 301)")) << all(t);
  InProcess p;
  p.add(t.device);
  ASSERT_EQ(p.bring_up(), "");
  master::CoeClient coe(p.master, 0);
  EXPECT_EQ(coe.upload(0x1600, 3).value_or(Bytes8{}), (Bytes8{0x10, 0x00, 0x40, 0x60}));
  EXPECT_EQ(coe.upload(0x1A00, 3).value_or(Bytes8{}), (Bytes8{0x10, 0x00, 0x41, 0x60}));
  EXPECT_EQ(coe.upload(0x60FE, 0).value_or(Bytes8{}), (Bytes8{0x02}));
  auto mapping = coe.read_pdo_mapping(0x1600);
  ASSERT_TRUE(mapping);
  EXPECT_EQ(*mapping, (std::vector<std::uint32_t>{0x607A0020, 0x60FE0120, 0x60400010}));
}

// Elmo Gold, revision 1.4.20: 1018h has no default for subindex 0 (the drive
// answers 4); DT1606 types its six entries as DINT/INT/UINT.
TEST(TwinLimitsElmo, SubindexZeroWithoutDefaultReadsTheHighestSubindex) {
  Twin t = import("elmo-gold-ecat.xml", 0x00030924, 0x00010420);
  EXPECT_TRUE(has_warning(t, 4928, "1018h:00 has no default; the twin's reads 4, the highest subindex (CiA 301)"))
      << all(t);
  EXPECT_TRUE(has_warning(t, 1734,
                          "1606h (PDO mapping) entries 01 (INTEGER32, 32 bits), 02 (INTEGER32, 32 bits), 03 "
                          "(INTEGER32, 32 bits), 04 (INTEGER32, 32 bits), 05 (INTEGER16, 16 bits), 06 (UNSIGNED16, "
                          "16 bits) are typed as the objects they map; a mapping entry is UNSIGNED32, so are the twin's"))
      << all(t);
  InProcess p;
  p.add(t.device);
  ASSERT_EQ(p.bring_up(), "");
  master::CoeClient coe(p.master, 0);
  EXPECT_EQ(coe.upload(0x1018, 0).value_or(Bytes8{}), (Bytes8{0x04}));
  auto past = coe.upload(0x1018, 5);
  ASSERT_FALSE(past);
  EXPECT_EQ(past.error().code, master::SdoAbortCode::SubindexNotFound);
  EXPECT_EQ(coe.upload(0x1606, 5).value_or(Bytes8{}), (Bytes8{0x10, 0x00, 0xB2, 0x60}));
}

// SMC EX250-SEN1: SM1 at 1000h is called Outputs, ControlByte 00h (the
// master reads it) and TxPdo 1A00h has Sm="1": the twin's SM1 is Inputs, and
// the master reaches Op with 1A00h's input bytes there.
TEST(TwinLimitsSmc, AnSmCalledOutputsWithAReadControlByteAndTxPdosIsInputs) {
  Twin t = import("smc-ex250-sen1.xml", 0x00FA6053, 0x00000000);
  EXPECT_TRUE(has_warning(t, 23,
                          "SM1 is called Outputs but its ControlByte #x00 makes it read by the master and the TxPdos "
                          "assigned to it say so; taken as Inputs"))
      << all(t);
  ASSERT_GE(t.device.sync_managers.size(), 2u);
  EXPECT_EQ(t.device.sync_managers[1].type, od::SmType::Inputs);
  EXPECT_EQ(t.device.sync_managers[1].start_address, 0x1000);
  ASSERT_EQ(t.device.tx_pdos.size(), 1u);
  EXPECT_EQ(t.device.tx_pdos[0].sm, std::optional<std::uint8_t>{1});
  // No mailbox: the master's start-up to Op with WKC checks is the chain
  // test's (twin_smc-ex250-sen1); here the twin is built and found.
  InProcess p;
  p.add(t.device);
  EXPECT_EQ(p.master.scan().value_or(0), 1u);
}

// Beckhoff CX2040 revision 0x00111B82: mailbox SM0 1000h and SM1 1200h of
// 1024 bytes each, SM3 at 1400h. The twin's mailboxes are 512 bytes (what
// fits; the device's other revisions give 512), and SDO works through them.
TEST(TwinLimitsCx2040, OverlappingMailboxSmsAreCutToWhatFits) {
  Twin t = import("beckhoff-cxxxxx.xml", 0x07F86034, 0x00111B82);
  EXPECT_TRUE(has_warning(t, 1149, "SM0 (MBoxOut) of 1024 bytes from 1000h reaches the next SM at 1200h; the twin's "
                                   "mailbox is 512 bytes"))
      << all(t);
  EXPECT_TRUE(has_warning(t, 1150, "SM1 (MBoxIn) of 1024 bytes from 1200h reaches the next SM at 1400h; the twin's "
                                   "mailbox is 512 bytes"))
      << all(t);
  ASSERT_GE(t.device.sync_managers.size(), 2u);
  EXPECT_EQ(t.device.sync_managers[0].default_size, 512);
  EXPECT_EQ(t.device.sync_managers[1].default_size, 512);
  EXPECT_EQ(t.device.sync_managers[1].max_size, 512);
  InProcess p;
  p.add(t.device);
  ASSERT_EQ(p.bring_up(), "");
  master::CoeClient coe(p.master, 0);
  EXPECT_EQ(coe.upload(0x1018, 2).value_or(Bytes8{}), (Bytes8{0x34, 0x60, 0xF8, 0x07}));
}

// Beckhoff EJ2521-0224: 7000h:12 "Target counter value" is UDINT (line 5494);
// the 16-bit alternative RxPdo 1601h maps it with 16 bits, 1602h with 32.
// The twin keeps the object at 32 bits, the 16-bit PDO maps its low bits,
// and the device XML says so (part="low"); the device XML loads again, and
// the firmware's SafeOp check accepts the fixed mapping (it refused 0x0025).
TEST(TwinLimitsEj2521, AShorterAlternativePdoMapsTheObjectsLowBits) {
  Twin t = import("beckhoff-ej2xxx.xml", 0x09D92852, 0x001000E0);
  EXPECT_TRUE(has_warning(t, 7454, "7000h:12 (32 bits) is mapped by PDO 1601h with 16 bits; the PDO carries its low 16 bits"))
      << all(t);
  const od::Entry* e = t.device.dictionary.find(0x7000, 0x12);
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->bit_length, 32);
  const od::Object* m = t.device.dictionary.find(0x1601);
  ASSERT_NE(m, nullptr);
  ASSERT_NE(m->find(1), nullptr);
  EXPECT_EQ(m->find(1)->default_value, (Bytes8{0x10, 0x12, 0x00, 0x70}));  // 7000h:12, 16 bits
  const std::string xml = esi::write_device_xml(t.device);
  EXPECT_NE(xml.find(R"(<Entry index="#x7000" sub="18" bits="16" part="low" name="Target counter value" />)"),
            std::string::npos);
  EXPECT_TRUE(esi::load_device_string(xml, "ej2521.xml"));
  InProcess p;
  p.add(t.device);
  ASSERT_EQ(p.bring_up(), "");
  auto r = p.cycle_once(std::chrono::milliseconds(1));
  ASSERT_TRUE(r);
  EXPECT_TRUE(r->ok());
}

// A device file that says part="low" where the entry is as long as its
// object is refused at the entry's line.
TEST(TwinLimitsEj2521, PartLowNeedsFewerBitsThanTheObject) {
  Twin t = import("beckhoff-ej2xxx.xml", 0x09D92852, 0x001000E0);
  std::string xml = esi::write_device_xml(t.device);
  const std::string from = R"(<Entry index="#x7000" sub="17" bits="16" name=)";
  const auto at = xml.find(from);
  ASSERT_NE(at, std::string::npos);
  xml.replace(at, from.size(), R"(<Entry index="#x7000" sub="17" bits="16" part="low" name=)");
  auto d = esi::load_device_string(xml, "ej2521.xml");
  ASSERT_FALSE(d);
  EXPECT_NE(d.error().to_string().find("part=\"low\" needs fewer bits (16) than the integer object's 16"), std::string::npos)
      << d.error().to_string();
}

}  // namespace
}  // namespace ecat::test
