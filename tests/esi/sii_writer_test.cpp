// SII writer: bytes checked against values computed by hand from ETG.2010 /
// shared/spec/sii-eeprom.md for the test servo of esi_test_device.cpp.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "esi/sii_crc.hpp"
#include "esi/sii_parser.hpp"
#include "esi/sii_writer.hpp"
#include "esi_test_device.hpp"

namespace ecat::esi {
namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes slice(const Bytes& b, std::size_t off, std::size_t n) {
  return Bytes(b.begin() + static_cast<std::ptrdiff_t>(off),
               b.begin() + static_cast<std::ptrdiff_t>(off + n));
}

TEST(SiiCrc, WorkedExampleFromSpec) {
  // sii-eeprom.md §2 worked example: 14 bytes -> 0xC1; the check over 15 bytes is 0.
  const std::array<std::uint8_t, 15> area = {0x05, 0x0C, 0x00, 0x44, 0x64, 0x00, 0x00, 0x00,
                                             0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xC1};
  EXPECT_EQ(sii::crc8(std::span(area).first(14)), 0xC1);
  EXPECT_EQ(sii::crc8(area), 0x00);
  const std::array<std::uint8_t, 14> zeros{};
  EXPECT_EQ(sii::crc8(zeros), 0x30);
  // Real EL2004 image (sii-eeprom.md §2): 04 01 00 00 00 00 0f 00 ... -> 0xD8.
  const std::array<std::uint8_t, 14> el2004 = {0x04, 0x01, 0, 0, 0, 0, 0x0F, 0, 0, 0, 0, 0, 0, 0};
  EXPECT_EQ(sii::crc8(el2004), 0xD8);
}

class SiiWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto r = write_sii(test::make_test_device());
    ASSERT_TRUE(r) << r.error();
    sii = *r;
  }
  Bytes sii;
};

TEST_F(SiiWriterTest, ConfigAreaAndChecksum) {
  ASSERT_EQ(sii.size(), 2048u);
  EXPECT_EQ(slice(sii, 0, 16), (Bytes{0x05, 0x0C, 0x00, 0x44, 0x64, 0x00, 0x00, 0x00, 0x00, 0x00,
                                      0x00, 0x00, 0x00, 0x00, 0xC1, 0x00}));
}

TEST_F(SiiWriterTest, IdentityMailboxSizeVersionWords) {
  EXPECT_EQ(slice(sii, 0x10, 16), (Bytes{0xBC, 0x0A, 0, 0, 0x34, 0x12, 0, 0, 0x01, 0x00, 0x02, 0x00,
                                         0, 0, 0, 0}));
  EXPECT_EQ(slice(sii, 0x20, 8), Bytes(8, 0));                     // delays, reserved
  EXPECT_EQ(slice(sii, 0x28, 8), Bytes(8, 0));                     // no bootstrap
  EXPECT_EQ(slice(sii, 0x30, 8), (Bytes{0x00, 0x10, 0x80, 0x00, 0x80, 0x10, 0x80, 0x00}));
  EXPECT_EQ(slice(sii, 0x38, 2), (Bytes{0x04, 0x00}));             // CoE only
  EXPECT_EQ(slice(sii, 0x3A, 0x7C - 0x3A), Bytes(0x7C - 0x3A, 0));  // reserved words
  EXPECT_EQ(slice(sii, 0x7C, 4), (Bytes{0x0F, 0x00, 0x01, 0x00}));  // 16 Kbit - 1, version 1
}

TEST_F(SiiWriterTest, StringsCategory) {
  EXPECT_EQ(slice(sii, 0x80, 4), (Bytes{0x0A, 0x00, 0x4B, 0x00}));  // 150 bytes = 75 words
  EXPECT_EQ(slice(sii, 0x84, 9), (Bytes{14, 6, 'T', 'S', '-', '1', '0', '0', 10}));
  // Last string "DC Sync0" ends the 150 bytes exactly.
  EXPECT_EQ(slice(sii, 0x84 + 150 - 9, 9), (Bytes{8, 'D', 'C', ' ', 'S', 'y', 'n', 'c', '0'}));
}

TEST_F(SiiWriterTest, GeneralCategory) {
  const std::size_t at = 0x84 + 150;
  Bytes expected = {0x1E, 0x00, 0x10, 0x00,  // type 30, 16 words
                    0x03, 0x00, 0x01, 0x02, 0x00, 0x2F, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
                    0x00, 0x00, 0x03, 0x00, 0x11, 0x00, 0x00, 0x00};
  expected.resize(4 + 32, 0);
  EXPECT_EQ(slice(sii, at, 36), expected);
}

TEST_F(SiiWriterTest, NotLrwFlag) {
  auto d = test::make_test_device();
  d.esc.no_lrw = true;
  auto r = write_sii(d);
  ASSERT_TRUE(r);
  EXPECT_EQ((*r)[0x84 + 150 + 4 + 0x0B], 0x02);
}

TEST_F(SiiWriterTest, FmmuAndSyncManagerCategories) {
  const std::size_t at = 0x84 + 150 + 36;
  EXPECT_EQ(slice(sii, at, 8), (Bytes{0x28, 0x00, 0x02, 0x00, 0x01, 0x02, 0x03, 0xFF}));
  EXPECT_EQ(slice(sii, at + 8, 36),
            (Bytes{0x29, 0x00, 0x10, 0x00,                           //
                   0x00, 0x10, 0x80, 0x00, 0x26, 0x00, 0x01, 0x01,   // SM0 MBoxOut
                   0x80, 0x10, 0x80, 0x00, 0x22, 0x00, 0x01, 0x02,   // SM1 MBoxIn
                   0x00, 0x11, 0x08, 0x00, 0x64, 0x00, 0x01, 0x03,   // SM2: 8 bytes from PDOs
                   0x00, 0x14, 0x06, 0x00, 0x20, 0x00, 0x01, 0x04}));  // SM3: 6 bytes
}

TEST_F(SiiWriterTest, PdoCategories) {
  const std::size_t at = 0x84 + 150 + 36 + 8 + 36;
  EXPECT_EQ(slice(sii, at, 28), (Bytes{0x32, 0x00, 0x0C, 0x00,                          //
                                       0x00, 0x1A, 0x02, 0x03, 0x00, 0x04, 0x13, 0x00,  //
                                       0x41, 0x60, 0x00, 0x05, 0x06, 0x10, 0x00, 0x00,  //
                                       0x64, 0x60, 0x00, 0x06, 0x04, 0x20, 0x00, 0x00}));
  EXPECT_EQ(slice(sii, at + 28, 44), (Bytes{0x33, 0x00, 0x14, 0x00,                          //
                                            0x00, 0x16, 0x04, 0x02, 0x00, 0x07, 0x02, 0x00,  //
                                            0x40, 0x60, 0x00, 0x08, 0x06, 0x10, 0x00, 0x00,  //
                                            0x7A, 0x60, 0x00, 0x09, 0x04, 0x20, 0x00, 0x00,  //
                                            0x60, 0x60, 0x00, 0x0A, 0x02, 0x08, 0x00, 0x00,  //
                                            0x00, 0x00, 0x00, 0x00, 0x00, 0x08, 0x00, 0x00}));
}

TEST_F(SiiWriterTest, DcCategoryEndAndFill) {
  const std::size_t at = 0x84 + 150 + 36 + 8 + 36 + 28 + 44;
  Bytes expected = {0x3C, 0x00, 0x18, 0x00};
  Bytes free_run(24, 0);
  free_run[0x10] = 0x01;  // SYNC0 factor 1
  free_run[0x12] = 11;
  free_run[0x13] = 12;
  Bytes dc(24, 0);
  dc[0x0F] = 0x03;  // AssignActivate 0x0300
  dc[0x10] = 0x01;
  dc[0x12] = 13;
  dc[0x13] = 14;
  expected.insert(expected.end(), free_run.begin(), free_run.end());
  expected.insert(expected.end(), dc.begin(), dc.end());
  EXPECT_EQ(slice(sii, at, 52), expected);
  EXPECT_EQ(slice(sii, at + 52, 2), (Bytes{0xFF, 0xFF}));
  for (std::size_t i = at + 54; i < sii.size(); ++i) ASSERT_EQ(sii[i], 0xFF) << i;
}

TEST_F(SiiWriterTest, BootstrapAndFoeWords) {
  auto d = test::make_test_device();
  d.bootstrap_supported = true;
  d.mailbox.foe = true;
  auto r = write_sii(d);
  ASSERT_TRUE(r);
  EXPECT_EQ(slice(*r, 0x28, 8), (Bytes{0x00, 0x10, 0x80, 0x00, 0x80, 0x10, 0x80, 0x00}));
  EXPECT_EQ(slice(*r, 0x38, 2), (Bytes{0x0C, 0x00}));
}

TEST(SiiWriter, Deterministic) {
  EXPECT_EQ(*write_sii(test::make_test_device()), *write_sii(test::make_test_device()));
}

TEST(SiiWriter, SmallEepromFallsBackStepByStep) {
  auto d = test::make_test_device();
  d.rx_pdos[0].entries[0].name = std::string(120, 'c');  // full image: 597 bytes
  d.esc.eeprom_bytes = 512;  // without entry names: 408 bytes
  EXPECT_EQ(write_sii_detailed(d)->detail, SiiDetail::NoEntryNames);
  d.esc.eeprom_bytes = 1024;
  EXPECT_EQ(write_sii_detailed(d)->detail, SiiDetail::Full);
  d.esc.eeprom_bytes = 512;
  auto r = write_sii_detailed(d);
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(r->detail, SiiDetail::NoEntryNames);
  auto parsed = parse_sii(r->bytes);
  ASSERT_TRUE(parsed);
  EXPECT_EQ(*parsed, sii_from_device(d, SiiDetail::NoEntryNames));
  EXPECT_EQ(parsed->rx_pdos.at(0).entries.at(0).name_idx, 0);
  EXPECT_EQ(parsed->string_at(parsed->rx_pdos.at(0).name_idx), "RxPDO 1");

  d.esc.eeprom_bytes = 256;
  r = write_sii_detailed(d);
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(r->detail, SiiDetail::NoPdoDc);
  parsed = parse_sii(r->bytes);
  ASSERT_TRUE(parsed);
  EXPECT_TRUE(parsed->tx_pdos.empty());
  EXPECT_TRUE(parsed->dc_modes.empty());
  EXPECT_EQ(parsed->strings, (std::vector<std::string>{"TS-100", "Test Servo", "Servo"}));
  EXPECT_EQ(parsed->sync_managers.size(), 4u);
}

TEST(SiiWriter, ErrorWhenNothingFits) {
  auto d = test::make_test_device();
  d.esc.eeprom_bytes = 256;
  d.identity.name = std::string(200, 'n');  // strings alone overflow 128 bytes of categories
  auto r = write_sii(d);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error(),
            "SII image needs 678 bytes but the EEPROM holds only 256 bytes (also without PDO "
            "entry names and without PDO/DC categories)");
}

TEST(SiiWriter, ErrorOnUnencodableSize) {
  auto d = test::make_test_device();
  d.esc.eeprom_bytes = 1000;
  auto r = write_sii(d);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("EEPROM size 1000 bytes cannot be encoded"), std::string::npos);
}

TEST(SiiWriter, FourKibSizeWord) {
  auto d = test::make_test_device();
  d.esc.eeprom_bytes = 4096;
  auto r = write_sii(d);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->size(), 4096u);
  EXPECT_EQ((*r)[0x7C], 31);
}

}  // namespace
}  // namespace ecat::esi

namespace ecat::esi {
namespace {

// EoE is announced only by a device that lists it (ETG.2010: word 0x1C bit 1,
// General byte 7 bit 0; ESI Mailbox/EoE); the test servo does not.
TEST(SiiEoeAnnouncement, OnlyForDevicesThatListEoe) {
  auto plain = write_sii(test::make_test_device());
  ASSERT_TRUE(plain);
  EXPECT_EQ(slice(*plain, 0x38, 2), (Bytes{0x04, 0x00}));    // CoE only
  EXPECT_EQ((*plain)[0x84 + 150 + 4 + 0x07], 0x00);         // General: EoE details 0
  auto d = test::make_test_device();
  d.mailbox.eoe = true;
  auto with = write_sii(d);
  ASSERT_TRUE(with);
  EXPECT_EQ(slice(*with, 0x38, 2), (Bytes{0x06, 0x00}));     // CoE + EoE
  EXPECT_EQ((*with)[0x84 + 150 + 4 + 0x07], 0x01);          // General: EoE enabled
}

}  // namespace
}  // namespace ecat::esi

#include "esi/esi_reader.hpp"
#include "esi/esi_writer.hpp"

namespace ecat::esi {
namespace {

// The ESI side: <EoE/> written for such a device, read back; a vendor ESI
// that lists EoE (Elmo Gold, shipped twin corpus) gives an EoE device.
TEST(EsiEoeAnnouncement, WrittenReadBackAndFromAVendorFile) {
  auto d = test::make_test_device();
  EXPECT_EQ(write_esi(d).find("<EoE"), std::string::npos);
  d.mailbox.eoe = true;
  const std::string xml = write_esi(d);
  EXPECT_NE(xml.find("<EoE"), std::string::npos);
  auto back = read_esi_string(xml, "eoe.xml");
  ASSERT_TRUE(back);
  EXPECT_TRUE(back->mailbox.eoe);
  auto elmo = read_esi(std::string(ECAT_SOURCE_DIR) + "/tests/data/esi-vendor/elmo-gold-ecat.xml");
  ASSERT_TRUE(elmo);
  EXPECT_TRUE(elmo->mailbox.eoe);
}

}  // namespace
}  // namespace ecat::esi
