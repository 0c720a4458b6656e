#include <gtest/gtest.h>

#include "tests/coe/rig.hpp"

namespace ecat::coe {
namespace {

using test::Frame;

// CoE header (service 8, SDO information) + info header + body; built with
// test::concat (see rig.hpp for why not by vector::insert).
Frame info_request(std::uint8_t opcode, const Frame& body) {
  return test::concat({0x00, 0x80, opcode, 0x00, 0x00, 0x00}, body);
}

std::vector<std::uint16_t> indices(const Frame& reply, std::size_t from) {
  std::vector<std::uint16_t> out;
  for (std::size_t i = from; i + 1 < reply.size(); i += 2) out.push_back(static_cast<std::uint16_t>(reply[i] | (reply[i + 1] << 8)));
  return out;
}

TEST(SdoInfo, OdListCountsAndMappableLists) {
  test::Rig rig;
  const std::size_t n = rig.device.dictionary.size();
  Frame counts = rig.sdo_request(info_request(0x01, {0x00, 0x00}));
  ASSERT_EQ(counts.size(), 18u);
  EXPECT_EQ(counts[2], 0x02);
  EXPECT_EQ(indices(counts, 8), (std::vector<std::uint16_t>{static_cast<std::uint16_t>(n), 3, 2, 0, 0}));
  Frame rx = rig.sdo_request(info_request(0x01, {0x02, 0x00}));
  EXPECT_EQ(rx, (Frame{0x00, 0x80, 0x02, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x70, 0x01, 0x70, 0x02, 0x70}));
  Frame tx = rig.sdo_request(info_request(0x01, {0x03, 0x00}));
  EXPECT_EQ(indices(tx, 8), (std::vector<std::uint16_t>{0x6000, 0x6001}));
  Frame bad = rig.sdo_request(info_request(0x01, {0x06, 0x00}));
  EXPECT_EQ(bad, (Frame{0x00, 0x80, 0x07, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x06}));
}

TEST(SdoInfo, LongListsComeInFragmentsInIndexOrder) {
  od::DeviceDescription d = test::make_device();
  for (std::uint16_t i = 0; i < 150; ++i) {
    (void)d.dictionary.put(test::var(static_cast<std::uint16_t>(0x3000 + i), "Filler", od::DataType::Unsigned8, 8, test::kRw));
  }
  test::Rig rig(std::move(d));
  const std::size_t n = rig.device.dictionary.size();
  // SM1 of 128 bytes: 57 indices in the first fragment, 58 in each later one.
  const std::size_t fragments = 1 + (n - 57 + 57) / 58;
  Frame first = rig.sdo_request(info_request(0x01, {0x01, 0x00}));
  ASSERT_EQ(first.size(), 8u + 2 * 57);
  EXPECT_EQ(first[2], 0x82);  // incomplete
  EXPECT_EQ(first[4] | (first[5] << 8), static_cast<int>(fragments - 1));
  std::vector<std::uint16_t> all = indices(first, 8);
  for (std::size_t k = 1; k < fragments; ++k) {
    auto next = rig.fetch();
    ASSERT_TRUE(next);
    const Frame payload(next->begin() + 6, next->end());
    const bool last = k + 1 == fragments;
    EXPECT_EQ(payload[2], last ? 0x02 : 0x82);
    EXPECT_EQ(payload[4] | (payload[5] << 8), static_cast<int>(fragments - 1 - k));
    auto more = indices(payload, 6);
    all.insert(all.end(), more.begin(), more.end());
  }
  EXPECT_FALSE(rig.fetch());
  ASSERT_EQ(all.size(), n);
  for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(all[i], rig.device.dictionary.objects()[i].index);
}

TEST(SdoInfo, ObjectDescription) {
  test::Rig rig;
  Frame id = rig.sdo_request(info_request(0x03, {0x18, 0x10}));
  Frame expect{0x00, 0x80, 0x04, 0x00, 0x00, 0x00, 0x18, 0x10, 0x23, 0x00, 0x04, 0x09};
  for (char c : std::string("Identity")) expect.push_back(static_cast<std::uint8_t>(c));
  EXPECT_EQ(id, expect);
  Frame var = rig.sdo_request(info_request(0x03, {0x00, 0x10}));
  EXPECT_EQ(Frame(var.begin(), var.begin() + 12), (Frame{0x00, 0x80, 0x04, 0x00, 0x00, 0x00, 0x00, 0x10, 0x07, 0x00, 0x00, 0x07}));
  EXPECT_EQ(rig.sdo_request(info_request(0x03, {0x55, 0x55})),
            (Frame{0x00, 0x80, 0x07, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x06}));
}

TEST(SdoInfo, EntryDescriptionWithValueInfo) {
  test::Rig rig;
  // 2000h: INTEGER16, rw, default 5, min -100, max 100; ask for everything.
  Frame e = rig.sdo_request(info_request(0x05, {0x00, 0x20, 0x00, 0x7F}));
  Frame expect{0x00, 0x80, 0x06, 0x00, 0x00, 0x00, 0x00, 0x20, 0x00,
               0x77,        // value info: access, category, mappable, default, min, max (no unit kept)
               0x03, 0x00,  // INTEGER16
               0x10, 0x00,  // 16 bits
               0x3F, 0x00,  // rw in every state
               0x05, 0x00, 0x9C, 0xFF, 0x64, 0x00};
  for (char c : std::string("Limited")) expect.push_back(static_cast<std::uint8_t>(c));
  EXPECT_EQ(e, expect);
  // Sub 0 of a record, as SOEM asks (value info 7): UINT8, ro, name.
  Frame s0 = rig.sdo_request(info_request(0x05, {0x18, 0x10, 0x00, 0x07}));
  EXPECT_EQ(Frame(s0.begin(), s0.begin() + 16),
            (Frame{0x00, 0x80, 0x06, 0x00, 0x00, 0x00, 0x18, 0x10, 0x00, 0x07, 0x05, 0x00, 0x08, 0x00, 0x07, 0x00}));
  EXPECT_EQ(std::string(s0.begin() + 16, s0.end()), "Number of entries");
  // A tx-mappable entry shows bit 7 of the access word.
  Frame m = rig.sdo_request(info_request(0x05, {0x00, 0x60, 0x00, 0x00}));
  EXPECT_EQ(m[14] | (m[15] << 8), 0x0087);
  EXPECT_EQ(rig.sdo_request(info_request(0x05, {0x18, 0x10, 0x09, 0x00})),
            (Frame{0x00, 0x80, 0x07, 0x00, 0x00, 0x00, 0x11, 0x00, 0x09, 0x06}));
}

}  // namespace
}  // namespace ecat::coe

namespace ecat::coe {
namespace {

// What SOEM's "slaveinfo -sdo" does (shared/spec/masters.md §1.5): OD list,
// then per object its description, per subindex 0..max its entry description
// (value info 7) and an upload. Every existing entry must answer.
TEST(SdoInfo, SlaveinfoWalkOverTheWholeDictionary) {
  test::Rig rig;
  std::vector<std::uint16_t> all;
  Frame reply = rig.sdo_request(info_request(0x01, {0x01, 0x00}));
  all = indices(reply, 8);
  while (reply[2] & 0x80) {
    auto next = rig.fetch();
    ASSERT_TRUE(next);
    reply = Frame(next->begin() + 6, next->end());
    auto more = indices(reply, 6);
    all.insert(all.end(), more.begin(), more.end());
  }
  ASSERT_EQ(all.size(), rig.device.dictionary.size());
  for (std::uint16_t index : all) {
    Frame od = rig.sdo_request(info_request(0x03, {static_cast<std::uint8_t>(index), static_cast<std::uint8_t>(index >> 8)}));
    ASSERT_EQ(od[2], 0x04) << std::hex << index;
    const std::uint8_t max_sub = od[10];
    for (unsigned sub = 0; sub <= max_sub; ++sub) {
      const auto lo = static_cast<std::uint8_t>(index);
      const auto hi = static_cast<std::uint8_t>(index >> 8);
      Frame oe = rig.sdo_request(info_request(0x05, {lo, hi, static_cast<std::uint8_t>(sub), 0x07}));
      const bool exists = rig.store.slot(index, static_cast<std::uint8_t>(sub)) != nullptr;
      ASSERT_EQ(oe[2], exists ? 0x06 : 0x07) << std::hex << index << ":" << sub;
      if (!exists) continue;
      Frame up = rig.sdo_request(test::sdo(0x40, index, static_cast<std::uint8_t>(sub)));
      const bool write_only = !rig.store.slot(index, static_cast<std::uint8_t>(sub))->entry->access.readable();
      if (write_only) {
        EXPECT_EQ(up[2], 0x80);
        EXPECT_EQ(up[9], 0x06);
      } else {
        EXPECT_EQ(up[1], 0x30) << std::hex << index << ":" << sub;
        EXPECT_EQ(up[2] & 0xE0, 0x40);
      }
    }
  }
}

}  // namespace
}  // namespace ecat::coe
