// Several CiA 402 axes in one device file (docs/device-format.md "Several
// axes"): the dual-axis Welcon as its manual lays it out (§7.1.4/7.1.5:
// +800h per axis, 2244h/2245h -> 2A42h/2A43h, PDOs 1610h-1619h and
// 1A10h-1A19h), and the loader's checks with file:line.
#include <gtest/gtest.h>

#include <algorithm>

#include "esi/device_loader.hpp"

namespace ecat::esi {
namespace {

const std::string kDir = std::string(ECAT_SOURCE_DIR) + "/xml/devices/";

// A little-endian value as a number.
std::uint64_t u(const od::Value& v) {
  std::uint64_t n = 0;
  for (std::size_t k = v.size(); k-- > 0;) n = n << 8 | v[k];
  return n;
}

const od::Pdo* find_pdo(const od::DeviceDescription& d, std::uint16_t index) {
  const auto& list = index < 0x1A00 ? d.rx_pdos : d.tx_pdos;
  auto it = std::find_if(list.begin(), list.end(), [&](const od::Pdo& p) { return p.index == index; });
  return it == list.end() ? nullptr : &*it;
}

class WelconDual : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    auto d = load_device_file(kDir + "welcon-servo-dual.xml");
    ASSERT_TRUE(d.has_value()) << d.error().to_string();
    dual = new od::DeviceDescription(std::move(*d));
    auto s = load_device_file(kDir + "welcon-servo.xml");
    ASSERT_TRUE(s.has_value()) << s.error().to_string();
    single = new od::DeviceDescription(std::move(*s));
  }
  static void TearDownTestSuite() {
    delete dual;
    delete single;
  }
  static inline od::DeviceDescription* dual = nullptr;
  static inline od::DeviceDescription* single = nullptr;
};

TEST_F(WelconDual, LayoutFromTheDriveElement) {
  ASSERT_TRUE(dual->drive.has_value());
  const od::AxisLayout& l = dual->drive->axes;
  EXPECT_EQ(l.axes, 2u);
  EXPECT_EQ(l.index_offset, 0x800u);
  EXPECT_EQ(l.pdo_offset, 0x10u);
  ASSERT_EQ(l.ranges.size(), 2u);
  EXPECT_EQ(l.ranges[0].first, 0x2000u);
  EXPECT_EQ(l.ranges[0].last, 0x27FFu);
  EXPECT_EQ(l.ranges[1].first, 0x6000u);
  EXPECT_EQ(l.ranges[1].last, 0x67FFu);
  EXPECT_EQ(l.object_index(2, 0x6040), 0x6840u);
  EXPECT_EQ(l.object_index(2, 0x2244), 0x2A42u);
  EXPECT_EQ(l.object_index(2, 0x2245), 0x2A43u);
  EXPECT_EQ(l.object_index(2, 0x2241), 0x2A41u);
  EXPECT_EQ(l.object_index(2, 0x1001), 0x1001u);  // common
  EXPECT_EQ(l.object_index(2, 0x5010), 0x5010u);  // common
  EXPECT_EQ(l.object_index(1, 0x6040), 0x6040u);
  EXPECT_EQ(single->drive->axes.axes, 1u);
  EXPECT_EQ(dual->identity.product_code, 0x20u);
  EXPECT_EQ(dual->identity.name, "Welcon Servo Drive (dual axis)");
}

// Every axis-1 object in 2000h-27FFh/6000h-67FFh has its axis-2 twin with the
// same entries; the common objects exist once.
TEST_F(WelconDual, EveryPerAxisObjectTwice) {
  const od::AxisLayout& l = dual->drive->axes;
  std::size_t per_axis = 0, common = 0;
  for (const od::Object& o : single->dictionary.objects()) {
    const std::uint16_t i = o.index;
    if (i >= 0x1600 && i < 0x1C00) continue;  // PDO mappings: below
    const od::Object* a1 = dual->dictionary.find(i);
    ASSERT_NE(a1, nullptr) << std::hex << i;
    if (!l.per_axis(i)) {
      ++common;
      // No copy: what lies at +800h is what the single-axis file has there (1C00h -> 2400h exists).
      const auto twin = static_cast<std::uint16_t>(i + 0x800u);
      EXPECT_EQ(dual->dictionary.find(twin) != nullptr, single->dictionary.find(twin) != nullptr) << std::hex << i;
      continue;
    }
    ++per_axis;
    const od::Object* a2 = dual->dictionary.find(l.object_index(2, i));
    ASSERT_NE(a2, nullptr) << std::hex << i;
    EXPECT_EQ(a2->name, o.name);
    ASSERT_EQ(a2->entries.size(), o.entries.size()) << std::hex << i;
    for (std::size_t k = 0; k < o.entries.size(); ++k) {
      EXPECT_EQ(a2->entries[k].type, o.entries[k].type) << std::hex << i;
      EXPECT_EQ(a2->entries[k].default_value, o.entries[k].default_value) << std::hex << i << ":" << k;
      EXPECT_EQ(a2->entries[k].bit_length, o.entries[k].bit_length) << std::hex << i << ":" << k;
    }
  }
  EXPECT_GT(per_axis, 180u);
  EXPECT_GT(common, 10u);
  // The exceptions: no 2A44h/2A45h.
  EXPECT_NE(dual->dictionary.find(0x2A42), nullptr);
  EXPECT_NE(dual->dictionary.find(0x2A43), nullptr);
  EXPECT_EQ(dual->dictionary.find(0x2A44), nullptr);
  EXPECT_EQ(dual->dictionary.find(0x2A45), nullptr);
  EXPECT_EQ(dual->dictionary.find(0x2A42)->name, dual->dictionary.find(0x2244)->name);
  // 6D02h = 6502h (both axes the same drive), 68E3h lists the same methods.
  EXPECT_EQ(u(dual->dictionary.find(0x6D02)->entries[0].default_value), 0x03AFu);
  EXPECT_EQ(u(dual->dictionary.find(0x6502)->entries[0].default_value), 0x03AFu);
  EXPECT_EQ(dual->dictionary.find(0x68E3)->entries.size(), dual->dictionary.find(0x60E3)->entries.size());
}

// 1610h-1619h / 1A10h-1A19h: axis 1's PDOs with 68xxh entries, same flags and
// default SM; 1C12h/1C13h assign 1608h+1618h / 1A08h+1A18h by default.
TEST_F(WelconDual, AxisTwoPdos) {
  ASSERT_EQ(dual->rx_pdos.size(), 20u);
  ASSERT_EQ(dual->tx_pdos.size(), 20u);
  for (const auto* list : {&single->rx_pdos, &single->tx_pdos}) {
    for (const od::Pdo& p : *list) {
      const od::Pdo* two = find_pdo(*dual, static_cast<std::uint16_t>(p.index + 0x10));
      ASSERT_NE(two, nullptr) << std::hex << p.index;
      EXPECT_EQ(two->name, p.name + " (axis 2)");
      EXPECT_EQ(two->fixed, p.fixed);
      EXPECT_EQ(two->sm, p.sm);
      ASSERT_EQ(two->entries.size(), p.entries.size());
      for (std::size_t k = 0; k < p.entries.size(); ++k) {
        EXPECT_EQ(two->entries[k].index, p.entries[k].index + 0x800u) << std::hex << p.index;
        EXPECT_EQ(two->entries[k].subindex, p.entries[k].subindex);
        EXPECT_EQ(two->entries[k].bit_length, p.entries[k].bit_length);
      }
    }
  }
  // The manual's RxPDO15 (1614h): 68400010h, 687A0020h, 68FE0120h.
  const od::Object* m = dual->dictionary.find(0x1614);
  ASSERT_NE(m, nullptr);
  const auto mapping = [&](std::uint8_t sub) { return u(m->find(sub)->default_value); };
  EXPECT_EQ(u(m->find(0)->default_value), 3u);
  EXPECT_EQ(mapping(1), 0x68400010u);
  EXPECT_EQ(mapping(2), 0x687A0020u);
  EXPECT_EQ(mapping(3), 0x68FE0120u);
  const od::Object* rx_assign = dual->dictionary.find(0x1C12);
  const od::Object* tx_assign = dual->dictionary.find(0x1C13);
  ASSERT_NE(rx_assign, nullptr);
  ASSERT_NE(tx_assign, nullptr);
  EXPECT_EQ(u(rx_assign->find(0)->default_value), 2u);
  EXPECT_EQ(u(rx_assign->find(1)->default_value), 0x1608u);
  EXPECT_EQ(u(rx_assign->find(2)->default_value), 0x1618u);
  EXPECT_EQ(u(tx_assign->find(0)->default_value), 2u);
  EXPECT_EQ(u(tx_assign->find(1)->default_value), 0x1A08u);
  EXPECT_EQ(u(tx_assign->find(2)->default_value), 0x1A18u);
}

// The checks, each with its file:line.
const std::string kName = std::string(ECAT_SOURCE_DIR) + "/tests/data/devices/inline.xml";

std::string axes_device(std::string_view drive) {
  return std::string(R"(<Device formatVersion="1">
  <Identity vendorId="0" name="T"/>
  <Objects>
    <Object index="#x6040" name="Controlword" type="UNSIGNED16" access="rw"/>
    <Object index="#x6041" name="Statusword" type="UNSIGNED16"/>
    <Object index="#x2000" name="Gain" type="UNSIGNED16" access="rw" default="7"/>
  </Objects>
)") + std::string(drive) + "</Device>\n";
}

LoadError error_of(const std::string& xml) {
  auto dev = load_device_string(xml, kName);
  EXPECT_FALSE(dev.has_value()) << "loaded although it should not";
  return dev ? LoadError{} : dev.error();
}

TEST(DeviceAxes, DefaultsAreTheProfileAreaAtPlus800h) {
  auto dev = load_device_string(axes_device("  <Drive axes=\"3\"/>\n"), kName);
  ASSERT_TRUE(dev.has_value()) << dev.error().to_string();
  for (int i : {0x6040, 0x6840, 0x7040, 0x6041, 0x6841, 0x7041}) EXPECT_NE(dev->dictionary.find(static_cast<std::uint16_t>(i)), nullptr) << std::hex << i;
  EXPECT_EQ(dev->dictionary.find(0x2800), nullptr);  // 2000h is common by default
  EXPECT_EQ(dev->drive->axes.pdo_offset, 0x10u);
}

TEST(DeviceAxes, ExplicitObjectAtTheCopysIndexWins) {
  std::string xml = axes_device("  <Drive axes=\"2\">\n    <AxisObjects from=\"#x2000\" to=\"#x20FF\"/>\n  </Drive>\n");
  xml.insert(xml.find("  </Objects>"), "    <Object index=\"#x2800\" name=\"Gain 2\" type=\"UNSIGNED16\" access=\"rw\" default=\"9\"/>\n");
  auto dev = load_device_string(xml, kName);
  ASSERT_TRUE(dev.has_value()) << dev.error().to_string();
  EXPECT_EQ(dev->dictionary.find(0x2800)->name, "Gain 2");
  EXPECT_EQ(u(dev->dictionary.find(0x2800)->entries[0].default_value), 9u);
  EXPECT_EQ(dev->dictionary.find(0x6840), nullptr);  // 6000h-67FFh is no longer per axis
}

TEST(DeviceAxes, Errors) {
  auto e = error_of(axes_device("  <Drive axes=\"9\"/>\n"));
  EXPECT_EQ(e.line, 8);
  EXPECT_EQ(e.message, "axes '9' is out of range (0..8)");
  e = error_of(axes_device("  <Drive axes=\"0\"/>\n"));
  EXPECT_EQ(e.message, "axes must be at least 1");
  e = error_of(axes_device("  <Drive axes=\"2\" axisPdoOffset=\"#x200\"/>\n"));
  EXPECT_EQ(e.message, "axisPdoOffset 0x200 does not fit 2 axes' PDOs into 1600h-17FFh and 1A00h-1BFFh");
  e = error_of(axes_device("  <Drive axes=\"2\" axisIndexOffset=\"#x400\"/>\n"));
  EXPECT_EQ(e.message, "axis 2 of 6000h (6400h) lies inside a per-axis range of axis 1");
  e = error_of(axes_device("  <Drive axes=\"8\">\n    <AxisObjects from=\"#xE000\" to=\"#xE0FF\"/>\n  </Drive>\n"));
  EXPECT_EQ(e.line, 9);
  EXPECT_EQ(e.message, "axis 8 of E000h-E0FFh would lie beyond FFFFh");
  e = error_of(axes_device("  <Drive axes=\"2\">\n    <AxisIndex index=\"#x6040\" axis=\"3\" at=\"#x7000\"/>\n  </Drive>\n"));
  EXPECT_EQ(e.line, 9);
  EXPECT_EQ(e.message, "AxisIndex axis 3 is not one of the axes 2..2");
  e = error_of(axes_device("  <Drive axes=\"2\">\n    <AxisIndex index=\"#x2000\" axis=\"2\" at=\"#x7000\"/>\n  </Drive>\n"));
  EXPECT_EQ(e.message, "AxisIndex 2000h is not in a per-axis range (AxisObjects)");
  e = error_of(axes_device("  <Drive axes=\"2\">\n    <AxisIndex index=\"#x6040\" axis=\"2\" at=\"#x6100\"/>\n  </Drive>\n"));
  EXPECT_EQ(e.message, "AxisIndex at 6100h lies inside a per-axis range of axis 1");
  e = error_of(axes_device("  <Drive axes=\"2\">\n    <AxisIndex index=\"#x6040\" axis=\"2\" at=\"#x6841\"/>\n  </Drive>\n"));
  EXPECT_EQ(e.message, "axis 2 copies of 6040h and 6041h would both be 6841h");
  e = error_of(axes_device("  <Drive axes=\"2\">\n    <AxisIndex index=\"#x6040\" axis=\"2\" at=\"#x7041\"/>\n"
                           "    <AxisIndex index=\"#x6041\" axis=\"2\" at=\"#x7041\"/>\n  </Drive>\n"));
  EXPECT_EQ(e.line, 5);  // the second object copied there
  EXPECT_EQ(e.message, "axis 2 copies of 6040h and 6041h would both be 7041h");
}

}  // namespace
}  // namespace ecat::esi
