// Number literals and value encoding of device files: every notation, type
// ranges (two's complement hex for signed types), reals, strings, octets.
#include <gtest/gtest.h>

#include "esi/device_values.hpp"

namespace ecat::esi {
namespace {

using od::DataType;
using od::Value;

Value ok(DataType t, std::uint16_t bits, std::string_view text) {
  auto v = encode_value(t, bits, text);
  EXPECT_TRUE(v.has_value()) << text << ": " << (v ? "" : v.error());
  return v ? *v : Value{};
}

std::string err(DataType t, std::uint16_t bits, std::string_view text) {
  auto v = encode_value(t, bits, text);
  EXPECT_FALSE(v.has_value()) << text;
  return v ? "" : v.error();
}

TEST(DeviceValues, IntegerNotations) {
  EXPECT_EQ(parse_integer("42")->magnitude, 42u);
  EXPECT_EQ(parse_integer("0x1C12")->magnitude, 0x1C12u);
  EXPECT_EQ(parse_integer("#x1c12")->magnitude, 0x1C12u);
  EXPECT_EQ(parse_integer(" +7 ")->magnitude, 7u);
  EXPECT_TRUE(parse_integer("-3")->negative);
  EXPECT_EQ(parse_integer("#xFFFFFFFFFFFFFFFF")->magnitude, 0xFFFFFFFFFFFFFFFFu);
  EXPECT_FALSE(parse_integer("#x10000000000000000"));  // 2^64
  EXPECT_FALSE(parse_integer("12a"));
  EXPECT_FALSE(parse_integer("0x"));
  EXPECT_FALSE(parse_integer(""));
  EXPECT_EQ(parse_unsigned("#xFFFF", 0xFFFF), 0xFFFFu);
  EXPECT_FALSE(parse_unsigned("#x10000", 0xFFFF));
  EXPECT_FALSE(parse_unsigned("-1", 0xFFFF));
  EXPECT_EQ(parse_signed("-128", -128, 127), -128);
  EXPECT_FALSE(parse_signed("128", -128, 127));
}

TEST(DeviceValues, UnsignedRanges) {
  EXPECT_EQ(ok(DataType::Unsigned8, 8, "255"), Value{0xFF});
  EXPECT_EQ(err(DataType::Unsigned8, 8, "256"), "value 256 does not fit UNSIGNED8");
  EXPECT_EQ(ok(DataType::Unsigned32, 32, "#x12345678"), (Value{0x78, 0x56, 0x34, 0x12}));
  EXPECT_EQ(ok(DataType::Unsigned24, 24, "#xABCDEF"), (Value{0xEF, 0xCD, 0xAB}));
  EXPECT_EQ(ok(DataType::Unsigned64, 64, "18446744073709551615"), Value(8, 0xFF));
  EXPECT_EQ(err(DataType::Unsigned16, 16, "-1"), "value -1 does not fit UNSIGNED16");
  EXPECT_EQ(ok(DataType::Bit3, 3, "7"), Value{7});
  EXPECT_EQ(err(DataType::Bit3, 3, "8"), "value 8 does not fit BIT3");
}

TEST(DeviceValues, SignedRangesAndTwosComplementHex) {
  EXPECT_EQ(ok(DataType::Integer8, 8, "-128"), Value{0x80});
  EXPECT_EQ(ok(DataType::Integer8, 8, "127"), Value{0x7F});
  EXPECT_EQ(err(DataType::Integer8, 8, "128"), "value 128 does not fit INTEGER8");
  EXPECT_EQ(err(DataType::Integer8, 8, "-129"), "value -129 does not fit INTEGER8");
  EXPECT_EQ(ok(DataType::Integer8, 8, "#xFF"), Value{0xFF});  // -1 written in hex
  EXPECT_EQ(err(DataType::Integer8, 8, "#x100"), "value #x100 does not fit INTEGER8");
  EXPECT_EQ(ok(DataType::Integer32, 32, "-2147483648"), (Value{0, 0, 0, 0x80}));
  EXPECT_EQ(ok(DataType::Integer64, 64, "-1"), Value(8, 0xFF));
  EXPECT_EQ(ok(DataType::Integer64, 64, "-9223372036854775808"), (Value{0, 0, 0, 0, 0, 0, 0, 0x80}));
}

TEST(DeviceValues, Booleans) {
  EXPECT_EQ(ok(DataType::Boolean, 1, "true"), Value{1});
  EXPECT_EQ(ok(DataType::Boolean, 1, "0"), Value{0});
  EXPECT_EQ(err(DataType::Boolean, 1, "yes"), "'yes' is not a BOOLEAN (true/false/1/0)");
}

TEST(DeviceValues, Reals) {
  EXPECT_EQ(ok(DataType::Real32, 32, "1.5"), (Value{0x00, 0x00, 0xC0, 0x3F}));
  EXPECT_EQ(ok(DataType::Real64, 64, "-2"), (Value{0, 0, 0, 0, 0, 0, 0, 0xC0}));
  EXPECT_EQ(err(DataType::Real32, 32, "1e39"), "value 1e39 does not fit REAL32");
  EXPECT_EQ(err(DataType::Real64, 64, "fast"), "'fast' is not a REAL64 number");
}

TEST(DeviceValues, Strings) {
  EXPECT_EQ(ok(DataType::VisibleString, 32, "abcd"), (Value{'a', 'b', 'c', 'd'}));
  EXPECT_EQ(ok(DataType::VisibleString, 32, "ab"), (Value{'a', 'b'}));
  EXPECT_EQ(err(DataType::VisibleString, 24, "abcd"), "string 'abcd' is 4 bytes, longer than its length 3");
  EXPECT_EQ(ok(DataType::UnicodeString, 32, "hi"), (Value{'h', 0, 'i', 0}));
  EXPECT_EQ(ok(DataType::OctetString, 24, "#x01 02 FF"), (Value{0x01, 0x02, 0xFF}));
  EXPECT_EQ(err(DataType::OctetString, 24, "0102030"), "'0102030' has an odd number of hex digits");
  EXPECT_EQ(err(DataType::OctetString, 16, "010203"), "value is 3 bytes, longer than its length 2");
  EXPECT_EQ(err(DataType::OctetString, 16, "zz"), "'zz' is not a hex byte string");
}

TEST(DeviceValues, CompareValues) {
  EXPECT_LT(compare_values(DataType::Integer16, ok(DataType::Integer16, 16, "-5"), ok(DataType::Integer16, 16, "3")), 0);
  EXPECT_GT(compare_values(DataType::Unsigned16, ok(DataType::Unsigned16, 16, "#xFFFB"), ok(DataType::Unsigned16, 16, "3")), 0);
  EXPECT_EQ(compare_values(DataType::Real32, ok(DataType::Real32, 32, "0.5"), ok(DataType::Real32, 32, "0.5")), 0);
  EXPECT_LT(compare_values(DataType::Real64, ok(DataType::Real64, 64, "-0.5"), ok(DataType::Real64, 64, "0.25")), 0);
}

}  // namespace
}  // namespace ecat::esi
