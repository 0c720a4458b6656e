// Issue 32 item 2: the mismatches of the vendor files that the import once
// accepted and the device-file loader then refused, each in a small file
// written for the test (tests/data/esi-mismatch/, README.md there), with the
// policy of docs/twins.md "Import policy": what the twin holds, the exact
// warning at the file's own line, and that the one judge (esi/twin_judge.hpp)
// accepts the twin.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "esi/device_loader.hpp"
#include "esi/esi_reader.hpp"
#include "esi/esi_writer.hpp"
#include "esi/esi_writer_device_xml.hpp"
#include "esi/twin_judge.hpp"
#include "esi/xml_chars.hpp"
#include "esi_test_device.hpp"
#include "twin_warnings.hpp"

namespace ecat::esi {
namespace {

using test::line_of;

using Read = test::FileRead;

Read read(const std::string& name) {
  const std::string path = std::string(ECAT_SOURCE_DIR) + "/tests/data/esi-mismatch/" + name;
  return test::read_judged(path, path);
}

std::string at(const Read& r, int line, const std::string& rest) {
  return r.file + ":" + std::to_string(line) + ": warning: " + rest;
}
// An element with another one before it on its line (`<Info><DefaultData>`)
// is placed by line:column (docs/twins.md "Positions in vendor files").
std::string at(const Read& r, int line, int column, const std::string& rest) {
  return r.file + ":" + std::to_string(line) + ":" + std::to_string(column) + ": warning: " + rest;
}

TEST(TwinMismatch, ZeroLengthPlaceholderEntryIsDropped) {
  const Read r = read("placeholder-entry.xml");
  ASSERT_EQ(r.d.tx_pdos.size(), 1u);
  EXPECT_TRUE(r.d.tx_pdos[0].entries.empty());
  const int line = line_of(r.text, "<BitLen>0</BitLen>") - 3;  // its <Entry>
  EXPECT_EQ(r.warnings, (std::vector<std::string>{
                            at(r, line, "Entry: PDO 1A00h entry 0000h:00 has BitLen 0: it maps nothing; dropped")}));
}

TEST(TwinMismatch, SmShorterThanItsAssignedPdosGrows) {
  const Read r = read("pdo-larger-than-sm.xml");
  ASSERT_EQ(r.d.sync_managers.size(), 2u);
  EXPECT_EQ(r.d.sync_managers[0].default_size, 12);
  EXPECT_EQ(r.d.sync_managers[1].max_size, 4);
  const int sm0 = line_of(r.text, "<Sm DefaultSize=\"6\"");
  const int sm1 = line_of(r.text, "<Sm MaxSize=\"2\"");
  EXPECT_EQ(r.warnings, (std::vector<std::string>{
                            at(r, sm0, "Sm: SM0 DefaultSize 6 is shorter than the PDOs assigned to it (12 bytes); "
                                       "masters size the SM from the PDOs, so does the twin: DefaultSize 12"),
                            at(r, sm1, "Sm: SM1 MaxSize 2 is shorter than the PDOs assigned to it (4 bytes); "
                                       "masters size the SM from the PDOs, so does the twin: MaxSize 4"),
                            // No dictionary: the mapped objects are made as process data.
                            at(r, line_of(r.text, "<TxPdo"),
                               "TxPdo: 6000h has no dictionary object; object created as process data: subindex 01 "
                               "(32 bits)"),
                            at(r, line_of(r.text, "<RxPdo"),
                               "RxPdo: 7000h has no dictionary object; object created as process data: subindex 01 "
                               "(32 bits), 02 (16 bits)"),
                            at(r, line_of(r.text, "<Index>#x1610<") - 1,
                               "RxPdo: 7010h has no dictionary object; object created as process data: subindex 01 "
                               "(32 bits), 02 (16 bits)"),
                        }));
}

TEST(TwinMismatch, DecimalPdoEntryIndexReadAsTheDictionarysHex) {
  const Read r = read("decimal-index.xml");
  ASSERT_EQ(r.d.rx_pdos.size(), 1u);
  ASSERT_EQ(r.d.tx_pdos.size(), 1u);
  EXPECT_EQ(r.d.rx_pdos[0].entries.at(0).index, 0x7000);
  EXPECT_EQ(r.d.tx_pdos[0].entries.at(0).index, 0x6000);
  EXPECT_EQ(r.d.tx_pdos[0].entries.at(1).index, 0x6010);
  ASSERT_NE(r.d.dictionary.find(0x6010), nullptr);  // created as process data
  EXPECT_EQ(r.d.dictionary.find(0x1B58), nullptr);
  const std::vector<std::string> expected = {
      at(r, line_of(r.text, "<Index>7000<"),
         "Index: Index '7000' is decimal by ETG.2000 (1B58h), in the communication area, which holds no process "
         "data; read as #x7000, the object the dictionary has"),
      at(r, line_of(r.text, "<Index>6000<"),
         "Index: Index '6000' is decimal by ETG.2000 (1770h), in the communication area, which holds no process "
         "data; read as #x6000, the object the dictionary has"),
      at(r, line_of(r.text, "<Index>6010<"),
         "Index: Index '6010' is decimal by ETG.2000 (177Ah), in the communication area, which holds no process "
         "data; read as #x6010, a process-data index"),
  };
  for (const auto& w : expected) {
    EXPECT_NE(std::find(r.warnings.begin(), r.warnings.end(), w), r.warnings.end()) << w;
  }
}

TEST(TwinMismatch, StringDefaultsGivenAsBytes) {
  const Read r = read("string-default-bytes.xml");
  const auto* control = r.d.dictionary.find(0x2000, 0);
  const auto* padded = r.d.dictionary.find(0x2001, 0);
  const auto* after_nul = r.d.dictionary.find(0x2002, 0);
  ASSERT_TRUE(control && padded && after_nul);
  EXPECT_TRUE(control->default_value.empty());
  EXPECT_EQ(control->bit_length, 32);
  EXPECT_EQ(padded->default_value, (od::Value{'A', 'B'}));
  EXPECT_EQ(after_nul->default_value, (od::Value{'A'}));
  EXPECT_EQ(r.d.dictionary.find(0x2003)->name, "Name?with a control character");
  EXPECT_EQ(r.warnings,
            (std::vector<std::string>{
                at(r, line_of(r.text, "01000000"), 23,
                   "DefaultData: STRING default 01000000 holds the byte 01h, a control character no VISIBLE_STRING "
                   "and no XML file holds; the entry keeps no default"),
                at(r, line_of(r.text, "4100420000"), 23,
                   "DefaultData: STRING default 4100420000 ends at its first 00 byte; the bytes after it are dropped"),
                at(r, line_of(r.text, "<Index>#x2003<") - 1,
                   "Object: the object's name holds the byte 01h at 4, a character XML 1.0 forbids; the twin has "
                   "'Name?with a control character'"),
            }));
}

// A modular device in an IO-Link master's shape: the ports' module PDOs carry
// no Sm (where they go depends on the configuration) while the device's own
// status PDO does, and 1C12h/1C13h give the default assignment with the
// default modules plugged. Before, the outputs were adopted (no RxPDO had an
// Sm) and the inputs dropped from 1C13h; now each placed PDO the dictionary
// assigns takes that Sm, and the twin's SII and 1C12h/1C13h list the same
// PDOs in the same order (ecat-conform's od.default_pdos_match_sii), the
// loaded device file too.
TEST(TwinMismatch, ModulePdosTakeTheDictionarysDefaultAssignment) {
  const Read r = read("module-assignment.xml");
  auto sms = [](const std::vector<od::Pdo>& pdos) {
    std::vector<std::pair<std::uint16_t, int>> out;
    for (const auto& p : pdos) out.emplace_back(p.index, p.sm ? *p.sm : -1);
    return out;
  };
  using List = std::vector<std::pair<std::uint16_t, int>>;
  EXPECT_EQ(sms(r.d.rx_pdos), (List{{0x1600, 2}, {0x1601, 2}}));
  EXPECT_EQ(sms(r.d.tx_pdos), (List{{0x1A00, 3}, {0x1A01, 3}, {0x1A80, 3}}));
  const int module_rx = line_of(r.text, "<Index DependOnSlot=\"true\">#x1600") - 1;
  const int module_tx = line_of(r.text, "<Index DependOnSlot=\"true\">#x1A00") - 1;
  const int assign_tx = line_of(r.text, "<Index>#x1C13<") - 1;
  EXPECT_EQ(r.warnings,
            (std::vector<std::string>{
                at(r, module_rx, "RxPdo: PDO 1600h has no Sm; assigned to SM2 as 1C12h:01 assigns it"),
                at(r, module_rx, "RxPdo: PDO 1601h has no Sm; assigned to SM2 as 1C12h:02 assigns it"),
                at(r, module_tx, "TxPdo: PDO 1A00h has no Sm; assigned to SM3 as 1C13h:02 assigns it"),
                at(r, module_tx, "TxPdo: PDO 1A01h has no Sm; assigned to SM3 as 1C13h:03 assigns it"),
                at(r, assign_tx,
                   "Object: 1C13h default (SI0 3 0x1a80 0x1a00 0x1a01) differs from the PDOs with Sm=\"3\" (SI0 3 "
                   "0x1a00 0x1a01 0x1a80); the SII's is used"),
            }));
  // The dictionary's assignment equals the SII's (the PDOs with that SM, in
  // the order the SII lists them), in the import and in the loaded file.
  auto agree = [](const od::DeviceDescription& d) {
    for (const auto& [assign, list, sm] : {std::tuple{std::uint16_t{0x1C12}, &d.rx_pdos, 2},
                                           std::tuple{std::uint16_t{0x1C13}, &d.tx_pdos, 3}}) {
      std::vector<std::uint64_t> sii, od;
      for (const auto& p : *list) {
        if (p.sm && *p.sm == sm) sii.push_back(p.index);
      }
      const od::Object* o = d.dictionary.find(assign);
      if (!o) return false;
      const auto n = o->find(0)->default_value.at(0);
      for (std::uint8_t k = 1; k <= n; ++k) {
        const auto& v = o->find(k)->default_value;
        od.push_back(static_cast<std::uint64_t>(v.at(0) | (v.at(1) << 8)));
      }
      if (sii != od) return false;
    }
    return true;
  };
  EXPECT_TRUE(agree(r.d));
  auto loaded = load_device_string(write_device_xml(r.d), "module-assignment.device.xml");
  ASSERT_TRUE(loaded) << loaded.error().to_string();
  EXPECT_TRUE(agree(*loaded));
}

// The same file with 1C13h:03 unreadable (DefaultData '5', found by
// fuzz_twin_judge): 1A01h, the second slot's copy of the module's TxPDO, is
// assigned by no 1C13h entry, but the ESI and device file describe it by
// the module's PDO, which took SM3 from 1C13h:02; so it takes SM3 at once,
// and 1C13h's default is compared with all three. Before, the import left
// it without Sm while every reload assigned it, and the written ESI was no
// fixed point (1C13h:00 3 against 2).
TEST(TwinMismatch, PlacedCopyOfAModulePdoTakesTheModulesSm) {
  std::ifstream in(std::string(ECAT_SOURCE_DIR) + "/tests/data/esi-mismatch/module-assignment.xml", std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  std::string text = s.str();
  const std::string entry = "<Name>SubIndex 003</Name><Info><DefaultData>011A</DefaultData>";
  const auto at_entry = text.find(entry);
  ASSERT_NE(at_entry, std::string::npos);
  text.replace(at_entry, entry.size(), "<Name>SubIndex 003</Name><Info><DefaultData>5</DefaultData>");
  const test::Read r = test::read(text);
  std::vector<std::pair<std::uint16_t, int>> tx;
  for (const auto& p : r.d.tx_pdos) tx.emplace_back(p.index, p.sm ? *p.sm : -1);
  EXPECT_EQ(tx, (std::vector<std::pair<std::uint16_t, int>>{{0x1A00, 3}, {0x1A01, 3}, {0x1A80, 3}}));
  const int module_tx = line_of(text, "<Index DependOnSlot=\"true\">#x1A00") - 1;
  EXPECT_TRUE(test::has_warning(r.warnings, module_tx, "PDO 1A01h has no Sm; assigned to SM3 as its module's PDO 1A00h is"))
      << test::all(r.warnings);
  auto judged = judge_twin(r.d);
  EXPECT_TRUE(judged) << judged.error();
}

// Item 1 (c): whatever a description holds, neither writer emits a character
// XML 1.0 forbids; control characters through a STRING default given as bytes
// (as the loader or a capture could hold them) become '?', length kept.
TEST(TwinMismatch, WritersNeverEmitForbiddenCharacters) {
  od::DeviceDescription d = test::make_test_device();
  d.identity.name = std::string("Servo\x01\x02", 7);
  od::Object o;
  o.index = 0x2100;
  o.code = od::ObjectCode::Var;
  o.name = "Str\x1F";
  od::Entry e;
  e.type = od::DataType::VisibleString;
  e.bit_length = 32;
  e.default_value = {0x01, 'A', 0x7F, 0x1B};
  e.name = o.name;
  o.entries.push_back(e);
  ASSERT_TRUE(d.dictionary.put(o));
  const std::string dx = write_device_xml(d);
  const std::string esi = write_esi(d);
  EXPECT_EQ(find_forbidden_xml_char(dx), std::nullopt);
  EXPECT_EQ(find_forbidden_xml_char(esi), std::nullopt);
  EXPECT_EQ(dx.find("&#"), std::string::npos);
  EXPECT_NE(dx.find("name=\"Str?\""), std::string::npos);
  EXPECT_NE(dx.find("default=\"?A\x7F?\""), std::string::npos);
  EXPECT_NE(esi.find("<DefaultString>?A\x7F?</DefaultString>"), std::string::npos);
  auto loaded = load_device_string(dx, "forbidden.device.xml");
  ASSERT_TRUE(loaded) << loaded.error().to_string();
  EXPECT_EQ(loaded->dictionary.find(0x2100, 0)->default_value, (od::Value{'?', 'A', 0x7F, '?'}));
  EXPECT_EQ(write_device_xml(*loaded), write_device_xml(*load_device_string(write_device_xml(*loaded), "x")));
}

TEST(TwinMismatch, ForbiddenCharacterScanner) {
  EXPECT_EQ(find_forbidden_xml_char("plain\t\r\ntext \xC3\xA9"), std::nullopt);
  EXPECT_EQ(find_forbidden_xml_char(std::string("a\0b", 3)), 1u);
  EXPECT_EQ(find_forbidden_xml_char("ab\x01"), 2u);
  EXPECT_EQ(find_forbidden_xml_char("\xFF"), 0u);           // no UTF-8
  EXPECT_EQ(find_forbidden_xml_char("\xC0\xAF"), 0u);       // overlong
  EXPECT_EQ(find_forbidden_xml_char("\xED\xA0\x80"), 0u);   // a surrogate
  EXPECT_EQ(find_forbidden_xml_char("x\xEF\xBF\xBF"), 1u);  // U+FFFF
  EXPECT_EQ(xml_safe_text("a\x01\xFF" "b"), "a??b");
}

}  // namespace
}  // namespace ecat::esi

namespace ecat::esi {
namespace {

// Findings of fuzz_twin_judge, kept as seeds in fuzz/corpus/fuzz_twin_judge/.
TEST(TwinJudgeRegressions, FuzzFindingsReachTheFixedPoint) {
  const auto dir = std::filesystem::path(ECAT_SOURCE_DIR) / "fuzz" / "corpus" / "fuzz_twin_judge";
  for (const auto& f : std::filesystem::directory_iterator(dir)) {
    if (!f.path().filename().string().starts_with("regress-")) continue;
    SCOPED_TRACE(f.path().filename().string());
    std::ifstream in(f.path(), std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    auto d = read_esi_string(s.str(), f.path().string());
    if (!d) continue;  // refused, with a message: allowed
    auto judged = judge_twin(*d);
    EXPECT_TRUE(judged) << judged.error();
    if (!judged && std::getenv("TWIN_JUDGE_DUMP")) {
      auto l1 = load_device_string(write_device_xml(*d), "x");
      const std::string e1 = write_esi(*l1);
      auto i2 = read_esi_string(e1, "e1");
      const std::string e2 = write_esi(*load_device_string(write_device_xml(*i2), "y"));
      std::ofstream("/tmp/tj_e1.xml") << e1;
      std::ofstream("/tmp/tj_e2.xml") << e2;
      std::ofstream("/tmp/tj_dx1.xml") << write_device_xml(*l1);
      std::ofstream("/tmp/tj_dx2.xml") << write_device_xml(*i2);
    }
  }
}

}  // namespace
}  // namespace ecat::esi
