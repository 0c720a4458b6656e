// Vendor files added to the corpus on branch twin-32 (issue 32 item 4,
// tests/data/esi-vendor/SOURCE.md), each with what its import says, exactly:
// Trinamic's TMC8462-BOB (no mailbox, PDO entry indices without '#x', SMs
// longer than their fixed PDOs) and Hilscher's NXHAT52 (a PDO that maps each
// of 16 subindices twice).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "esi/esi_reader.hpp"
#include "esi/twin_judge.hpp"
#include "twin_warnings.hpp"

namespace ecat::esi {
namespace {

using test::line_of;

using Read = test::FileRead;

Read read(const std::string& name) {
  const std::string path = std::string(ECAT_SOURCE_DIR) + "/tests/data/esi-vendor/" + name;
  return test::read_judged(path, name);
}

// The 1-based line of the last `needle` in `text`.
int last_line_of(const std::string& text, const std::string& needle) {
  const auto at = text.rfind(needle);
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

std::string at(const std::string& file, int line, const std::string& rest) {
  return file + ":" + std::to_string(line) + ": warning: " + rest;
}

TEST(TwinVendorAdditions, TrinamicTmc8462DecimalIndicesAndFixedSmSizes) {
  const std::string f = "trinamic-tmc8462-bob.xml";
  const Read r = read(f);
  // The entry indices '7000', '7001', '6003' are decimal by ETG.2000 (1B58h,
  // 1B59h, 1773h: the communication area); without a dictionary the hex
  // reading is taken (docs/twins.md "Import policy").
  ASSERT_EQ(r.d.rx_pdos.size(), 1u);
  ASSERT_EQ(r.d.tx_pdos.size(), 1u);
  ASSERT_EQ(r.d.rx_pdos[0].entries.size(), 2u);
  EXPECT_EQ(r.d.rx_pdos[0].entries[0].index, 0x7000);
  EXPECT_EQ(r.d.rx_pdos[0].entries[1].index, 0x7001);
  EXPECT_EQ(r.d.tx_pdos[0].entries.at(0).index, 0x6003);
  // Fixed process data: SM0 and SM1 are as long as their PDOs (6 and 2 bytes),
  // not the file's 8 (ecat-conform's sii.sm_sizes_fit_pdos).
  ASSERT_EQ(r.d.sync_managers.size(), 2u);
  EXPECT_EQ(r.d.sync_managers[0].default_size, 6);
  EXPECT_EQ(r.d.sync_managers[1].default_size, 2);
  const int sm0 = line_of(r.text, "<Sm DefaultSize=\"8\" StartAddress=\"#x1000\"");
  const int sm1 = line_of(r.text, "<Sm DefaultSize=\"8\" StartAddress=\"#x1100\"");
  EXPECT_EQ(r.warnings,
            (std::vector<std::string>{
                at(f, line_of(r.text, "<Info>"), "Info: not modelled; ignored"),
                at(f, line_of(r.text, "<Index>7000<"),
                   "Index: Index '7000' is decimal by ETG.2000 (1B58h), in the communication area, which holds no "
                   "process data; read as #x7000, a process-data index"),
                at(f, line_of(r.text, "<Index>7001<"),
                   "Index: Index '7001' is decimal by ETG.2000 (1B59h), in the communication area, which holds no "
                   "process data; read as #x7001, a process-data index"),
                at(f, line_of(r.text, "<Index>6003<"),
                   "Index: Index '6003' is decimal by ETG.2000 (1773h), in the communication area, which holds no "
                   "process data; read as #x6003, a process-data index"),
                at(f, line_of(r.text, "<Category>"), "Category: not modelled; ignored"),
                at(f, last_line_of(r.text, "<ImageData16x14>"), "ImageData16x14: not modelled; ignored"),
                at(f, sm0,
                   "Sm: SM0 DefaultSize 8 is longer than the PDOs assigned to it (6 bytes) and the process data is "
                   "fixed (no PDO assignment or configuration); masters size the SM from the PDOs, so does the twin: "
                   "DefaultSize 6"),
                at(f, sm1,
                   "Sm: SM1 DefaultSize 8 is longer than the PDOs assigned to it (2 bytes) and the process data is "
                   "fixed (no PDO assignment or configuration); masters size the SM from the PDOs, so does the twin: "
                   "DefaultSize 2"),
                at(f, line_of(r.text, "<TxPdo"),
                   "TxPdo: 6003h has no dictionary object; object created as process data: subindex 01 (16 bits)"),
                at(f, line_of(r.text, "<RxPdo"),
                   "RxPdo: 7000h has no dictionary object; object created as process data: subindex 00 (32 bits)"),
                at(f, line_of(r.text, "<RxPdo"),
                   "RxPdo: 7001h has no dictionary object; object created as process data: subindex 00 (16 bits)"),
            }));
}

TEST(TwinVendorAdditions, HilscherNxhat52MapsEachSubindexTwice) {
  const std::string f = "hilscher-nxhat52-32bytes.xml";
  const Read r = read(f);
  // 32 one-byte entries over 2000h:01..10h (3000h:01..10h): kept as written,
  // both halves of the 32 bytes map the same 16 entries.
  ASSERT_EQ(r.d.rx_pdos.size(), 1u);
  ASSERT_EQ(r.d.rx_pdos[0].entries.size(), 32u);
  EXPECT_EQ(r.d.rx_pdos[0].entries[16].index, 0x2000);
  EXPECT_EQ(r.d.rx_pdos[0].entries[16].subindex, 1);
  const od::Object* out = r.d.dictionary.find(0x2000);
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(out->entries.size(), 17u);  // subindex 0 and 01..10h
  std::string subs;
  for (int k = 1; k <= 16; ++k) subs += (k > 1 ? ", " : "") + fmt::format("{:02X} (8 bits)", k);
  EXPECT_EQ(r.warnings,
            (std::vector<std::string>{
                at(f, line_of(r.text, "<URL>"), "URL: not modelled; ignored"),
                at(f, last_line_of(r.text, "<ImageData16x14>"), "ImageData16x14: not modelled; ignored"),
                at(f, line_of(r.text, "<RxPdo"),
                   "RxPdo: 2000h has no dictionary object; object created as process data: subindex " + subs),
                at(f, line_of(r.text, "<TxPdo"),
                   "TxPdo: 3000h has no dictionary object; object created as process data: subindex " + subs),
            }));
}

}  // namespace
}  // namespace ecat::esi
