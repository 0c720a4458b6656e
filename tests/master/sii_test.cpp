#include "master/sii.hpp"

#include <gtest/gtest.h>

#include "test_sii_image.hpp"

namespace ecat::master {
namespace {

TEST(SiiCrc, MatchesWorkedExampleAndRealImages) {
  // sii-eeprom.md §2: worked example -> 0xC1, all-zero area -> 0x30.
  const std::uint8_t example[14]{0x05, 0x0C, 0x00, 0x44, 0x64, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  EXPECT_EQ(sii::config_crc(example), 0xC1);
  const std::uint8_t zeros[14]{};
  EXPECT_EQ(sii::config_crc(zeros), 0x30);
  // EL2004 configuration area (ethercrab dump) -> 0xD8.
  const std::uint8_t el2004[14]{0x04, 0x01, 0, 0, 0, 0, 0x0F, 0, 0, 0, 0, 0, 0, 0};
  EXPECT_EQ(sii::config_crc(el2004), 0xD8);
}

TEST(SiiParse, ReadsFixedWordsAndEveryCategory) {
  const auto img = test::test_sii_image();
  auto info = parse_sii(img);
  ASSERT_TRUE(info.has_value());
  EXPECT_TRUE(info->checksum_ok);
  EXPECT_EQ(info->checksum, 0xC1);
  EXPECT_EQ(info->vendor_id, test::kVendor);
  EXPECT_EQ(info->product_code, test::kProduct);
  EXPECT_EQ(info->revision, 2u);
  EXPECT_EQ(info->serial, 7u);
  EXPECT_EQ(info->rx_mailbox_offset, 0x1000);
  EXPECT_EQ(info->rx_mailbox_size, 128);
  EXPECT_EQ(info->tx_mailbox_offset, 0x1080);
  EXPECT_TRUE(info->has_coe());
  EXPECT_EQ(info->device_name(), "TestSlave");
  EXPECT_EQ(info->string(2), "Outputs");
  EXPECT_EQ(info->string(3), "");
  ASSERT_TRUE(info->general.has_value());
  EXPECT_EQ(info->general->coe_details & sii::kCoeCompleteAccess, sii::kCoeCompleteAccess);
  EXPECT_EQ(info->general->ebus_current_ma, 100);
  EXPECT_EQ(info->general->physical_ports, 0x11);
  EXPECT_EQ(info->fmmu_usage, (std::vector<std::uint8_t>{1, 2, 3}));
  ASSERT_EQ(info->sync_managers.size(), 4u);
  EXPECT_EQ(info->sync_managers[0].control, 0x26);
  EXPECT_EQ(info->sync_managers[3].start, 0x1400);
  EXPECT_EQ(info->sync_managers[3].type, sii::kSmTypeInputs);
  ASSERT_EQ(info->tx_pdos.size(), 1u);
  EXPECT_EQ(info->tx_pdos[0].index, 0x1A00);
  EXPECT_EQ(info->tx_pdos[0].entries[0].index, 0x6000);
  EXPECT_EQ(info->default_pdo_bits(true, 3), 32u);
  EXPECT_EQ(info->default_pdo_bits(false, 2), 16u);
  EXPECT_EQ(info->category_order, (std::vector<std::uint16_t>{10, 30, 40, 41, 50, 51}));
  EXPECT_EQ(sii_image_length(img), img.size() - 2);
}

TEST(SiiParse, MalformedImagesAreErrors) {
  auto img = test::test_sii_image();
  EXPECT_EQ(parse_sii(ConstBytes(img.data(), 100)).error(), SiiParseError::TooShort);
  // Cut before the end marker.
  EXPECT_FALSE(parse_sii(ConstBytes(img.data(), img.size() - 4)).has_value());
  // GENERAL must be 16 words (IgH).
  auto bad = img;
  const std::size_t general_len = sii::kFixedAreaBytes + 2 + 2 + 20 + 2;  // after STRINGS (20 bytes)
  ASSERT_EQ(load_le<std::uint16_t>(bad.data() + general_len - 2), 30);
  store_le(bad.data() + general_len, std::uint16_t{15});
  EXPECT_FALSE(parse_sii(bad).has_value());
  // A category length past the end.
  auto huge = img;
  store_le(huge.data() + sii::kFixedAreaBytes + 2, std::uint16_t{0x7FFF});
  EXPECT_EQ(parse_sii(huge).error(), SiiParseError::CategoryBeyondEnd);
  // Bad CRC is reported, not fatal.
  auto crc = img;
  crc[0] ^= 1;
  auto info = parse_sii(crc);
  ASSERT_TRUE(info.has_value());
  EXPECT_FALSE(info->checksum_ok);
}

}  // namespace
}  // namespace ecat::master
