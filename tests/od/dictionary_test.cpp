#include "od/dictionary.hpp"

#include <gtest/gtest.h>

namespace ecat::od {
namespace {

Object var(std::uint16_t index, DataType t) {
  Object o;
  o.index = index;
  o.code = ObjectCode::Var;
  o.type = t;
  Entry e;
  e.subindex = 0;
  e.type = t;
  e.bit_length = fixed_bit_size(t);
  o.entries.push_back(e);
  return o;
}

TEST(Dictionary, KeepsObjectsSortedAndFindsThem) {
  Dictionary d;
  ASSERT_TRUE(d.put(var(0x6041, DataType::Unsigned16)));
  ASSERT_TRUE(d.put(var(0x1000, DataType::Unsigned32)));
  ASSERT_TRUE(d.put(var(0x6040, DataType::Unsigned16)));
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(d.objects()[0].index, 0x1000);
  EXPECT_EQ(d.objects()[1].index, 0x6040);
  EXPECT_EQ(d.objects()[2].index, 0x6041);
  EXPECT_NE(d.find(0x6040, 0), nullptr);
  EXPECT_EQ(d.find(0x6040, 1), nullptr);
  EXPECT_EQ(d.find(0x2000), nullptr);
}

TEST(Dictionary, RefusesDuplicateSubindexAndVarWithTwoEntries) {
  Dictionary d;
  Object o = var(0x2000, DataType::Unsigned8);
  o.code = ObjectCode::Record;
  o.entries.push_back(o.entries.front());
  auto r = d.put(o);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("2000h"), std::string::npos);

  Object v = var(0x2001, DataType::Unsigned8);
  Entry e1 = v.entries.front();
  e1.subindex = 1;
  v.entries.push_back(e1);
  EXPECT_FALSE(d.put(v));
  EXPECT_TRUE(d.empty());
}

TEST(DataType, NamesRoundTrip) {
  EXPECT_EQ(canopen_name(DataType::Unsigned16), "UNSIGNED16");
  EXPECT_EQ(from_canopen_name("INTEGER32"), DataType::Integer32);
  EXPECT_EQ(esi_base_name(DataType::Integer32), "DINT");
  EXPECT_EQ(from_esi_base_name("BIT3"), DataType::Bit3);
  EXPECT_EQ(fixed_bit_size(DataType::Unsigned24), 24);
  EXPECT_EQ(fixed_bit_size(DataType::VisibleString), 0);
}

}  // namespace
}  // namespace ecat::od
