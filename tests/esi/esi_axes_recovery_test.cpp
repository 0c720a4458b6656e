// The axes of a multi-axis ESI (docs/twins.md "Axes of a multi-axis ESI"):
// the dual-axis Welcon's ESI (written from xml/devices/welcon-servo-dual.xml,
// objects of axis 2 at +800h, PDOs at +10h) read back as a vendor file gives
// a device model with two axes again, whose device file loads with the same
// objects and PDOs; a file whose axis 2 lacks an object of axis 1 keeps one
// axis and says why at its Dictionary line.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "esi/device_loader.hpp"
#include "esi/esi_reader.hpp"
#include "esi/esi_writer.hpp"
#include "esi/esi_writer_device_xml.hpp"

namespace ecat::esi {
namespace {

std::vector<std::uint16_t> indices(const od::DeviceDescription& d) {
  std::vector<std::uint16_t> out;
  for (const auto& o : d.dictionary.objects()) out.push_back(o.index);
  return out;
}

std::vector<std::uint16_t> pdo_indices(const std::vector<od::Pdo>& list) {
  std::vector<std::uint16_t> out;
  for (const auto& p : list) out.push_back(p.index);
  return out;
}

std::string all(const std::vector<EsiWarning>& w) {
  std::string s;
  for (const auto& x : w) s += x.to_string("t.xml") + "\n";
  return s;
}

od::DeviceDescription welcon_dual() {
  auto d = load_device_file(std::filesystem::path(ECAT_SOURCE_DIR) / "xml" / "devices" / "welcon-servo-dual.xml");
  EXPECT_TRUE(d) << d.error().to_string();
  return d ? *d : od::DeviceDescription{};
}

TEST(EsiAxesRecovery, TheDualAxisWelconReadBackFromItsEsiHasTwoAxes) {
  const od::DeviceDescription original = welcon_dual();
  ASSERT_TRUE(original.drive);
  ASSERT_EQ(original.drive->axes.axes, 2u);
  const std::string esi = write_esi(original);
  std::vector<EsiWarning> w;
  auto read = read_esi_string(esi, "welcon-dual.xml", {}, &w);
  ASSERT_TRUE(read) << read.error().to_string();
  ASSERT_TRUE(read->drive);
  const od::AxisLayout& l = read->drive->axes;
  EXPECT_EQ(l.axes, 2u);
  EXPECT_EQ(l.index_offset, 0x800);
  EXPECT_EQ(l.pdo_offset, 0x10);  // axis 2's PDOs 1610h/1A10h against 1600h/1A00h
  EXPECT_EQ(l.object_index(2, 0x6040), 0x6840);
  EXPECT_EQ(l.pdo_index(2, 0x1600), 0x1610);
  EXPECT_FALSE(std::any_of(w.begin(), w.end(), [](const EsiWarning& x) { return x.element == "Dictionary"; }))
      << all(w);
  // Its device file says <Drive axes="2" ...> and loads with the same objects and PDOs.
  const std::string xml = write_device_xml(*read);
  EXPECT_NE(xml.find("axes=\"2\""), std::string::npos);
  EXPECT_NE(xml.find("axisPdoOffset=\"#x0010\""), std::string::npos);
  auto back = load_device_string(xml, "twin.xml");
  ASSERT_TRUE(back) << back.error().to_string();
  ASSERT_TRUE(back->drive);
  EXPECT_EQ(back->drive->axes.axes, 2u);
  EXPECT_EQ(indices(*back), indices(*read));
  EXPECT_EQ(pdo_indices(back->rx_pdos), pdo_indices(read->rx_pdos));
  EXPECT_EQ(pdo_indices(back->tx_pdos), pdo_indices(read->tx_pdos));
}

TEST(EsiAxesRecovery, AnAxisWithoutAnObjectOfAxisOneKeepsOneAxisAndSaysWhy) {
  od::DeviceDescription d = welcon_dual();
  ASSERT_NE(d.dictionary.find(0x687A), nullptr);  // axis 2's target position
  std::string esi = write_esi(d);
  // Drop axis 2's 607Ah (687Ah) from the dictionary and from its PDOs.
  const std::string open = "<Index>#x687A</Index>";
  for (auto at = esi.find(open); at != std::string::npos; at = esi.find(open)) {
    const auto obj = esi.rfind("<Object>", at);
    const auto entry = esi.rfind("<Entry>", at);
    if (obj != std::string::npos && (entry == std::string::npos || obj > entry)) {
      esi.erase(obj, esi.find("</Object>", at) + std::string("</Object>").size() - obj);
    } else {
      esi.erase(entry, esi.find("</Entry>", at) + std::string("</Entry>").size() - entry);
    }
  }
  std::vector<EsiWarning> w;
  auto read = read_esi_string(esi, "t.xml", {}, &w);
  ASSERT_TRUE(read) << read.error().to_string();
  ASSERT_TRUE(read->drive);
  EXPECT_EQ(read->drive->axes.axes, 1u);
  const auto line = 1 + static_cast<int>(std::count(esi.begin(), esi.begin() + static_cast<std::ptrdiff_t>(
                                                                                  esi.find("<Dictionary>")),
                                                    '\n'));
  EXPECT_TRUE(std::any_of(w.begin(), w.end(), [&](const EsiWarning& x) {
    return x.element == "Dictionary" && x.line == line &&
           x.message == "2 CiA 402 axes (6040h/6041h at +800h steps), but axis 2 has no 687Ah (axis 1's 607Ah); the "
                        "twin runs axis 1's state machine only";
  })) << all(w);
  EXPECT_TRUE(load_device_string(write_device_xml(*read), "twin.xml"));
}

TEST(EsiAxesRecovery, ASingleAxisDriveIsLeftAlone) {
  auto d = load_device_file(std::filesystem::path(ECAT_SOURCE_DIR) / "xml" / "devices" / "welcon-servo.xml");
  ASSERT_TRUE(d) << d.error().to_string();
  std::vector<EsiWarning> w;
  auto read = read_esi_string(write_esi(*d), "t.xml", {}, &w);
  ASSERT_TRUE(read) << read.error().to_string();
  ASSERT_TRUE(read->drive);
  EXPECT_EQ(read->drive->axes.axes, 1u);
  EXPECT_EQ(write_device_xml(*read).find("axes="), std::string::npos);
}

}  // namespace
}  // namespace ecat::esi
