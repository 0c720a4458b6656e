// Bad input never crashes or hangs: every prefix of a vendor ESI and random
// or mutated SII images give either a result or an error (run under ASan/UBSan
// in CI), and out-of-range numbers in an ESI give warnings.
#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <sstream>

#include "esi/esi_reader.hpp"
#include "esi/sii_parser.hpp"
#include "esi/sii_writer.hpp"
#include "esi_test_device.hpp"

namespace ecat::esi {
namespace {

std::string vendor_file() {
  std::ifstream in(std::string(ECAT_SOURCE_DIR) + "/tests/data/esi/vendor-drives.xml");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(EsiRobustness, EveryPrefixOfAVendorFile) {
  const std::string xml = vendor_file();
  ASSERT_GT(xml.size(), 1000u);
  int errors = 0;
  for (std::size_t n = 0; n < xml.size(); n += 53) {
    std::vector<EsiWarning> warnings;
    auto r = read_esi_string(std::string_view(xml).substr(0, n), "cut.xml", {}, &warnings);
    if (!r) {
      ++errors;
      EXPECT_FALSE(r.error().message.empty());
    }
  }
  EXPECT_GT(errors, 0);
}

TEST(EsiRobustness, OutOfRangeNumbersWarn) {
  const std::string xml = R"(<EtherCATInfo><Vendor><Id>1</Id></Vendor><Descriptions><Devices>
<Device Physics="YY"><Type ProductCode="1" RevisionNo="1">X</Type><Name>X</Name><GroupType>G</GroupType>
<Sm StartAddress="#x12345" ControlByte="#x26" Enable="1">MBoxOut</Sm>
<RxPdo><Index>#x1600</Index><Name>P</Name><Entry><Index>#x6040</Index><BitLen>300</BitLen></Entry></RxPdo>
</Device></Devices></Descriptions></EtherCATInfo>)";
  std::vector<EsiWarning> w;
  auto d = read_esi_string(xml, "range.xml", {}, &w);
  ASSERT_GE(w.size(), 2u);
  EXPECT_EQ(w[0].to_string("range.xml"),
            "range.xml:3: warning: Sm: StartAddress '#x12345' is not a number in range; taken as 0");
  EXPECT_EQ(w[1].to_string("range.xml"),
            "range.xml:4:43: warning: Entry: BitLen '300' is not a number in range; taken as 0");
  // What is left (a mailbox SM of no size at 0000h) no device file can say:
  // the import refuses it at the Sm's line (issue 32, one judge).
  ASSERT_FALSE(d);
  EXPECT_EQ(d.error().to_string(), "range.xml:3: Sm: mailbox SyncManager 0 needs a size (the twin cannot represent "
                                   "this; the import refuses it)");
}

TEST(EsiRobustness, ReservedConfigWordsWarn) {
  // LAN9252-style ConfigData with word 5 set: the model keeps words 0-4 only.
  const std::string xml = R"(<EtherCATInfo><Vendor><Id>1</Id></Vendor><Descriptions><Devices>
<Device Physics="YY"><Type ProductCode="1" RevisionNo="1">X</Type><Name>X</Name><GroupType>G</GroupType>
<Eeprom><ByteSize>2048</ByteSize><ConfigData>8003006EFF00FF000000C0400000</ConfigData></Eeprom>
</Device></Devices></Descriptions></EtherCATInfo>)";
  std::vector<EsiWarning> w;
  auto d = read_esi_string(xml, "cfg.xml", {}, &w);
  ASSERT_TRUE(d);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].to_string("cfg.xml"), "cfg.xml:3:34: warning: ConfigData: bytes after word 4 (reserved "
                                       "words 5-6) are not modelled; written as 0");
  EXPECT_EQ(d->esc.pdi_control, 0x0380);
  EXPECT_EQ(d->esc.pdi_configuration, 0x6E00);
  EXPECT_EQ(d->esc.sync_impulse_length, 0x00FF);
  EXPECT_EQ(d->esc.pdi_configuration2, 0x00FF);
}

TEST(SiiRobustness, RandomAndMutatedImages) {
  std::mt19937 rng(12345);  // fixed seed: reproducible
  std::uniform_int_distribution<int> byte(0, 255);
  const auto good = *write_sii(test::make_test_device());
  for (int round = 0; round < 2000; ++round) {
    std::vector<std::uint8_t> img;
    if (round % 2 == 0) {
      img.resize(static_cast<std::size_t>(128 + byte(rng) * 4));
      for (auto& b : img) b = static_cast<std::uint8_t>(byte(rng));
    } else {
      img = good;
      for (int k = 0; k < 8; ++k) {
        img[128 + static_cast<std::size_t>(byte(rng)) % 400] = static_cast<std::uint8_t>(byte(rng));
      }
    }
    auto r = parse_sii(img);
    if (!r) {
      EXPECT_FALSE(r.error().empty());
    }
  }
}

}  // namespace
}  // namespace ecat::esi
