#include "common/le.hpp"

#include <array>

#include <gtest/gtest.h>

namespace ecat {
namespace {

TEST(ByteReader, ReadsLittleEndianFields) {
  const std::array<std::uint8_t, 7> buf{0x34, 0x12, 0x78, 0x56, 0x34, 0x12, 0xAA};
  ByteReader r(buf);
  EXPECT_EQ(r.u16(), 0x1234);
  EXPECT_EQ(r.u32(), 0x12345678u);
  EXPECT_EQ(r.u8(), 0xAA);
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.remaining(), 0u);
}

TEST(ByteReader, ReadPastEndFailsAndStaysFailed) {
  const std::array<std::uint8_t, 3> buf{1, 2, 3};
  ByteReader r(buf);
  EXPECT_EQ(r.u32(), 0u);
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.u8(), 0u);  // even though a byte would remain
  EXPECT_TRUE(r.bytes(1).empty());
}

TEST(ByteWriter, WritesAndRefusesOverflow) {
  std::array<std::uint8_t, 5> buf{};
  ByteWriter w(buf);
  w.u16(0xBEEF);
  w.u16(0x0102);
  EXPECT_TRUE(w.ok());
  w.u16(0xFFFF);  // only one byte left
  EXPECT_FALSE(w.ok());
  EXPECT_EQ(buf, (std::array<std::uint8_t, 5>{0xEF, 0xBE, 0x02, 0x01, 0x00}));
}

}  // namespace
}  // namespace ecat
