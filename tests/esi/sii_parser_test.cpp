// SII parser: decodes what the writer makes (parse(encode(x)) == x), reads a
// hand-made image, and rejects damaged input with a message, never a crash.
#include <gtest/gtest.h>

#include <vector>

#include "esi/sii_parser.hpp"
#include "esi/sii_writer.hpp"
#include "esi_test_device.hpp"

namespace ecat::esi {
namespace {

TEST(SiiParser, RoundTripsTheWriter) {
  const SiiImage img = sii_from_device(test::make_test_device());
  auto bytes = encode_sii(img, 2048);
  ASSERT_TRUE(bytes) << bytes.error();
  auto parsed = parse_sii(*bytes);
  ASSERT_TRUE(parsed) << parsed.error();
  EXPECT_EQ(*parsed, img);
  EXPECT_TRUE(parsed->checksum_ok);
  EXPECT_EQ(parsed->eeprom_bytes(), 2048u);
  EXPECT_EQ(parsed->string_at(parsed->general->name_idx), "Test Servo");
  EXPECT_EQ(parsed->string_at(parsed->rx_pdos.at(0).entries.at(1).name_idx), "Target position");
}

TEST(SiiParser, RoundTripsRawAndOddCategories) {
  SiiImage img = sii_from_device(test::make_test_device());
  img.fmmus = {1, 2, 0};  // odd count: padded with FFh, pad dropped again
  img.other_categories.push_back({0x0001, {0xDE, 0xAD, 0xBE, 0xEF}});
  img.strings.push_back("odd");  // odd-length STRINGS category
  img.execution_delay = 7;
  img.config.station_alias = 0x1234;
  auto bytes = encode_sii(img, 4096);
  ASSERT_TRUE(bytes);
  auto parsed = parse_sii(*bytes);
  ASSERT_TRUE(parsed) << parsed.error();
  img.size_word = 31;
  EXPECT_EQ(*parsed, img);
}

TEST(SiiParser, DetectsBadChecksum) {
  auto bytes = *write_sii(test::make_test_device());
  bytes[0] ^= 0x01;
  auto parsed = parse_sii(bytes);
  ASSERT_TRUE(parsed);
  EXPECT_FALSE(parsed->checksum_ok);
  bytes[14] = 0xA4;  // debug value 88A4h disables the check
  bytes[15] = 0x88;
  EXPECT_TRUE(parse_sii(bytes)->checksum_ok);
}

TEST(SiiParser, RejectsShortImage) {
  std::vector<std::uint8_t> bytes(100, 0);
  auto parsed = parse_sii(bytes);
  ASSERT_FALSE(parsed);
  EXPECT_EQ(parsed.error(), "SII image is 100 bytes, shorter than the 128-byte fixed area");
}

TEST(SiiParser, RejectsMissingEnd) {
  std::vector<std::uint8_t> bytes(132, 0);
  bytes[128] = 0x28;  // FMMU category, 0 words, then the image ends
  auto parsed = parse_sii(bytes);
  ASSERT_FALSE(parsed);
  EXPECT_EQ(parsed.error(),
            "SII category list runs past the end (byte 132) without an END marker (FFFFh)");
}

TEST(SiiParser, RejectsCategoryPastEnd) {
  std::vector<std::uint8_t> bytes(136, 0);
  bytes[128] = 0x0A;  // STRINGS
  bytes[130] = 0x10;  // 16 words, only 2 present
  auto parsed = parse_sii(bytes);
  ASSERT_FALSE(parsed);
  EXPECT_EQ(parsed.error(),
            "SII category 10 at word 0040h: length 16 words runs past the end of the 136-byte image");
}

TEST(SiiParser, RejectsTruncatedPdoAndStrings) {
  std::vector<std::uint8_t> bytes(128, 0);
  // TXPDO with 2 entries declared but only one present.
  const std::vector<std::uint8_t> pdo = {0x32, 0x00, 0x08, 0x00, 0x00, 0x1A, 0x02, 0x03,
                                         0x00, 0x00, 0x00, 0x00, 0x41, 0x60, 0x00, 0x00,
                                         0x06, 0x10, 0x00, 0x00, 0xFF, 0xFF};
  auto b1 = bytes;
  b1.insert(b1.end(), pdo.begin(), pdo.end());
  auto p1 = parse_sii(b1);
  ASSERT_FALSE(p1);
  EXPECT_EQ(p1.error(),
            "SII category 50 at word 0040h: PDO 1A00h declares 2 entries but the category ends "
            "after 1");
  const std::vector<std::uint8_t> strings = {0x0A, 0x00, 0x02, 0x00, 0x02, 0x05, 'a', 'b', 0xFF, 0xFF};
  auto b2 = bytes;
  b2.insert(b2.end(), strings.begin(), strings.end());
  auto p2 = parse_sii(b2);
  ASSERT_FALSE(p2);
  EXPECT_EQ(p2.error(), "SII category 10 at word 0040h: string 1 of 2 runs past the category");
}

TEST(SiiParser, RejectsBadSyncmAndShortGeneral) {
  std::vector<std::uint8_t> bytes(128, 0);
  auto b1 = bytes;
  for (std::uint8_t v : std::vector<std::uint8_t>{0x29, 0x00, 0x03, 0x00, 0, 0, 0, 0, 0, 0, 0xFF, 0xFF}) {
    b1.push_back(v);
  }
  ASSERT_FALSE(parse_sii(b1));
  EXPECT_EQ(parse_sii(b1).error(),
            "SII category 41 at word 0040h: SYNCM length 6 bytes is not a multiple of 8");
  auto b2 = bytes;
  for (std::uint8_t v : std::vector<std::uint8_t>{0x1E, 0x00, 0x01, 0x00, 0, 0, 0xFF, 0xFF}) {
    b2.push_back(v);
  }
  EXPECT_EQ(parse_sii(b2).error(), "SII category 30 at word 0040h: GENERAL has 2 bytes, needs 32");
}

TEST(SiiParser, NeverCrashesOnTruncations) {
  const auto bytes = *write_sii(test::make_test_device());
  // Every prefix that cuts the category list must give an error, not a crash;
  // the whole list (with END) parses.
  EXPECT_TRUE(parse_sii(std::span(bytes).first(488)));
  for (std::size_t n = 0; n < 488; ++n) {  // END marker at bytes 486..487
    auto parsed = parse_sii(std::span(bytes).first(n));
    EXPECT_FALSE(parsed) << n;
  }
}

}  // namespace
}  // namespace ecat::esi
