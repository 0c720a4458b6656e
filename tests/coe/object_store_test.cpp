#include "coe/object_store.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <utility>
#include <vector>

#include "tests/coe/test_device.hpp"

namespace ecat::coe {
namespace {

class Refuser : public ObjectHooks {
 public:
  Expected<void, SdoAbort> on_write(ObjectStore&, const WriteRequest& r) noexcept override {
    ++checks;
    if (r.state != od::EsmState::PreOp) return fail(SdoAbort::DataTransferDeviceState);
    return {};
  }
  void after_write(ObjectStore&, std::uint16_t, std::uint8_t sub) noexcept override { last_written = sub; }
  void on_read(ObjectStore& s, std::uint16_t index, std::uint8_t sub) noexcept override {
    (void)s.set<std::uint16_t>(index, sub, 0x4242);
  }
  int checks = 0;
  int last_written = -1;
};

class ObjectStoreTest : public ::testing::Test {
 protected:
  od::DeviceDescription device = test::make_device();
  ObjectStore store{device.dictionary};
};

TEST_F(ObjectStoreTest, DefaultsAreLoaded) {
  EXPECT_EQ(store.get<std::uint32_t>(0x1000, 0), 0x00020192u);
  EXPECT_EQ(store.get<std::int16_t>(0x2000, 0), 5);
  EXPECT_EQ(store.get<std::uint8_t>(0x1018, 0), 4);
  EXPECT_EQ(store.get<std::uint32_t>(0x1018, 4), 0x0BADCAFEu);
  auto name = store.value(0x1008, 0);
  EXPECT_EQ(std::string(name.begin(), name.end()), "ecat test");
  EXPECT_EQ(store.slot(0x2002, 0)->capacity, 65536u);
  EXPECT_EQ(store.length(*store.slot(0x2002, 0)), 0u);
}

TEST_F(ObjectStoreTest, TypedSetAndSignExtension) {
  ASSERT_TRUE(store.set<std::int16_t>(0x2000, 0, -3));
  EXPECT_EQ(store.get<std::int16_t>(0x2000, 0), -3);
  EXPECT_EQ(store.get<std::int32_t>(0x2000, 0), -3);  // sign-extended from 16 bits
  const auto v = store.value(0x2000, 0);
  EXPECT_EQ(v[0], 0xFD);
  EXPECT_EQ(v[1], 0xFF);
  EXPECT_EQ(store.set<std::uint8_t>(0x2000, 9, 1).error(), SdoAbort::NoSubindex);
  EXPECT_EQ(store.set<std::uint8_t>(0x5555, 0, 1).error(), SdoAbort::NoObject);
}

TEST_F(ObjectStoreTest, WriteChecksLengthAndRange) {
  std::array<std::uint8_t, 3> three{1, 2, 3};
  std::array<std::uint8_t, 1> one{1};
  std::array<std::uint8_t, 2> too_high{101, 0};
  std::array<std::uint8_t, 2> too_low{0x9B, 0xFF};  // -101
  std::array<std::uint8_t, 2> ok{0x9C, 0xFF};       // -100
  EXPECT_EQ(store.write({0x2000, 0, three}).error(), SdoAbort::LengthTooHigh);
  EXPECT_EQ(store.write({0x2000, 0, one}).error(), SdoAbort::LengthTooLow);
  EXPECT_EQ(store.write({0x2000, 0, too_high}).error(), SdoAbort::ValueTooHigh);
  EXPECT_EQ(store.write({0x2000, 0, too_low}).error(), SdoAbort::ValueTooLow);
  EXPECT_EQ(store.get<std::int16_t>(0x2000, 0), 5);  // unchanged by the refused writes
  ASSERT_TRUE(store.write({0x2000, 0, ok}));
  EXPECT_EQ(store.get<std::int16_t>(0x2000, 0), -100);
}

TEST_F(ObjectStoreTest, BitFieldsMustFitTheirLength) {
  std::array<std::uint8_t, 1> eight{8};
  std::array<std::uint8_t, 1> seven{7};
  EXPECT_EQ(store.write({0x2005, 2, eight}).error(), SdoAbort::ValueRange);
  EXPECT_TRUE(store.write({0x2005, 2, seven}));
  std::array<std::uint8_t, 1> two{2};
  EXPECT_EQ(store.write({0x2005, 1, two}).error(), SdoAbort::ValueRange);
}

TEST_F(ObjectStoreTest, HooksRefuseReactAndCompute) {
  Refuser hooks;
  ASSERT_TRUE(store.set_hooks(0x2003, &hooks));
  EXPECT_FALSE(store.set_hooks(0x4444, &hooks));
  std::array<std::uint8_t, 2> v{0x34, 0x12};
  EXPECT_EQ(store.write({0x2003, 1, v, od::EsmState::SafeOp}).error(), SdoAbort::DataTransferDeviceState);
  EXPECT_EQ(store.get<std::uint16_t>(0x2003, 1), 0x1111);
  EXPECT_EQ(hooks.last_written, -1);
  ASSERT_TRUE(store.write({0x2003, 1, v, od::EsmState::PreOp}));
  EXPECT_EQ(store.get<std::uint16_t>(0x2003, 1), 0x1234);
  EXPECT_EQ(hooks.last_written, 1);
  EXPECT_EQ(hooks.checks, 2);
  std::array<std::uint8_t, 4> out{};
  auto n = store.read(0x2003, 2, out);
  ASSERT_TRUE(n);
  EXPECT_EQ(*n, 2u);
  EXPECT_EQ(out[0], 0x42);
  EXPECT_EQ(out[1], 0x42);
}

TEST_F(ObjectStoreTest, VariableLengthStrings) {
  std::array<std::uint8_t, 5> data{1, 2, 3, 4, 5};
  ASSERT_TRUE(store.write({0x2002, 0, data}));
  EXPECT_EQ(store.value(0x2002, 0).size(), 5u);
  std::vector<std::uint8_t> big(65537, 0xAA);
  EXPECT_EQ(store.write({0x2002, 0, big}).error(), SdoAbort::LengthTooHigh);
  EXPECT_EQ(store.value(0x2002, 0).size(), 5u);
  store.reset_to_defaults();
  EXPECT_EQ(store.value(0x2002, 0).size(), 0u);
}

// A string's length lives in the value buffer before its value: writing one
// leaves its neighbours' values alone, and a 1008h default keeps its length.
TEST_F(ObjectStoreTest, StringLengthsDoNotTouchOtherValues) {
  const std::vector<std::uint8_t> before(store.value(0x1008, 0).begin(), store.value(0x1008, 0).end());
  const std::uint32_t device_type = store.get<std::uint32_t>(0x1000, 0);
  std::vector<std::uint8_t> text(65536, 0x55);
  ASSERT_TRUE(store.write({0x2002, 0, text}));
  EXPECT_EQ(store.length(*store.slot(0x2002, 0)), 65536u);
  ASSERT_TRUE(store.write({0x2002, 0, ConstBytes{}}));
  EXPECT_EQ(store.length(*store.slot(0x2002, 0)), 0u);
  EXPECT_EQ(std::vector<std::uint8_t>(store.value(0x1008, 0).begin(), store.value(0x1008, 0).end()), before);
  EXPECT_EQ(store.length(*store.slot(0x1008, 0)), 9u);  // "ecat test"
  EXPECT_EQ(store.get<std::uint32_t>(0x1000, 0), device_type);
  for (const ObjectStore::Slot& s : store.slots()) {
    const std::vector<std::uint8_t> v(store.value(s).begin(), store.value(s).end());
    if (s.variable()) continue;
    EXPECT_EQ(v.size(), s.capacity);
  }
}

// Every slot names its object: the index the store files it under.
TEST_F(ObjectStoreTest, IndexOfEverySlot) {
  std::size_t n = 0;
  for (const od::Object& o : device.dictionary.objects()) {
    for (const od::Entry& e : o.entries) {
      const ObjectStore::Slot* s = store.slot(o.index, e.subindex);
      ASSERT_NE(s, nullptr);
      EXPECT_EQ(store.index_of(*s), o.index);
      EXPECT_EQ(s->entry, &e);
      ++n;
    }
  }
  EXPECT_EQ(n, store.slots().size());
  static_assert(sizeof(void*) != 8 || sizeof(ObjectStore::Slot) == 16, "one slot per entry and slave: 16 bytes");
}

// The values the PDO copies move every cycle lie at the front of the value
// buffer (issue 30 item 1: a drive's cyclic values in few cache lines):
// first those the default assignment maps, in the order of their images
// (1C12h's 1600h: 7000h, 7001h; 1C13h's 1A00h: 6000h, 6001h), so that a copy
// plan moves each image as one block; then the other PDO-mappable numbers
// (7002h, in 1601h, which 1C12h does not assign); then the rest. No two
// values (nor a string's length before its value) share a byte.
TEST_F(ObjectStoreTest, MappableNumbersLieFirstAndTogether) {
  const std::pair<std::uint16_t, std::uint32_t> kFront[] = {
      {0x7000, 0}, {0x7001, 2}, {0x6000, 3}, {0x6001, 7}, {0x7002, 8}};
  for (const auto& [index, offset] : kFront) {
    const ObjectStore::Slot* s = store.slot(index, 0);
    ASSERT_NE(s, nullptr);
    EXPECT_EQ(s->offset, offset) << std::hex << index;
    EXPECT_EQ(store.values() + s->offset, store.storage(*store.slot(index, 0)).data());
  }
  EXPECT_EQ(store.get<std::uint32_t>(0x6000, 0), 0x11223344u);
  EXPECT_EQ(store.get<std::uint8_t>(0x6001, 0), 0x55u);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> spans;  // [begin, end) incl. a string's length
  for (const ObjectStore::Slot& s : store.slots()) {
    if (s.entry->access.rx_mappable() || s.entry->access.tx_mappable()) continue;
    EXPECT_GE(s.offset, 12u) << std::hex << store.index_of(s);
    spans.emplace_back(s.offset - (s.variable() ? ObjectStore::kLengthPrefix : 0), s.offset + s.capacity);
  }
  for (const auto& [index, offset] : kFront) {
    spans.emplace_back(offset, offset + store.slot(index, 0)->capacity);
  }
  std::sort(spans.begin(), spans.end());
  for (std::size_t i = 1; i < spans.size(); ++i) EXPECT_LE(spans[i - 1].second, spans[i].first) << i;
}

}  // namespace
}  // namespace ecat::coe
