// Which ESI of an --esi-dir serves an ENI slave (docs/twins.md "ENI: revision
// matching"): the exact revision first; else the same product code and major
// revision word, the highest minor not above the ENI's, else the lowest above;
// never another major word. A compatible choice is a warning at the slave's
// Info line naming the file and revision; the twin carries the ENI's revision.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>

#include <unistd.h>

#include "esi/eni_devices.hpp"
#include "esi/eni_reader.hpp"

namespace ecat::esi {
namespace {

namespace fs = std::filesystem;

std::string esi_with_revision(std::uint32_t revision) {
  return fmt::format(R"(<?xml version="1.0"?>
<EtherCATInfo Version="1.6">
  <Vendor><Id>#x00000002</Id><Name>Rev Test</Name></Vendor>
  <Descriptions>
    <Groups><Group><Type>G</Type><Name>G</Name></Group></Groups>
    <Devices>
      <Device Physics="YY">
        <Type ProductCode="#x044C2C52" RevisionNo="#x{:08X}">RT-1</Type>
        <Name>RT-1 rev {:08X}</Name>
        <GroupType>G</GroupType>
      </Device>
    </Devices>
  </Descriptions>
</EtherCATInfo>
)",
                     revision, revision);
}

class EniRevisionMatch : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::path(::testing::TempDir()) / ("eni-revision-match-" + std::to_string(::getpid()));  // tests run side by side
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (std::uint32_t r : {0x00110000u, 0x00110005u, 0x00120001u}) {
      std::ofstream(dir / fmt::format("rt-{:08x}.xml", r)) << esi_with_revision(r);
    }
  }
  void TearDown() override { fs::remove_all(dir); }

  EniNetwork net(std::uint32_t revision) const {
    EniNetwork n;
    n.file = "net.xml";
    EniSlave s;
    s.name = "Coupler";
    s.vendor_id = 2;
    s.product_code = 0x044C2C52;
    s.revision = revision;
    s.line = 3;
    s.info_line = 4;
    n.slaves.push_back(s);
    return n;
  }
  fs::path dir;
};

TEST_F(EniRevisionMatch, ExactRevisionIsTakenWithoutWarning) {
  std::vector<EsiWarning> w;
  auto devs = eni_devices(net(0x00110005), dir, &w);
  ASSERT_TRUE(devs) << devs.error().to_string();
  EXPECT_EQ(fs::path((*devs)[0].esi_file).filename(), "rt-00110005.xml");
  EXPECT_EQ((*devs)[0].device.identity.revision, 0x00110005u);
  for (const auto& x : w) EXPECT_EQ(x.message.find("no ESI in the directory"), std::string::npos) << x.message;
}

TEST_F(EniRevisionMatch, SameMajorWordHighestMinorNotAbove) {
  std::vector<EsiWarning> w;
  auto devs = eni_devices(net(0x00110003), dir, &w);
  ASSERT_TRUE(devs) << devs.error().to_string();
  EXPECT_EQ(fs::path((*devs)[0].esi_file).filename(), "rt-00110000.xml");
  EXPECT_EQ((*devs)[0].device.identity.revision, 0x00110003u);  // the ENI's
  ASSERT_FALSE(w.empty());
  EXPECT_EQ(w.front().line, 4);
  EXPECT_EQ(w.front().message,
            "no ESI in the directory has revision #x00110003; the dictionary comes from rt-00110000.xml revision "
            "#x00110000 (same product code and major revision word 0011h: compatible), the SII carries the ENI's "
            "revision");
}

TEST_F(EniRevisionMatch, SameMajorWordLowestAboveWhenNoneBelow) {
  std::vector<EsiWarning> w;
  auto devs = eni_devices(net(0x00120000), dir, &w);
  ASSERT_TRUE(devs) << devs.error().to_string();
  EXPECT_EQ(fs::path((*devs)[0].esi_file).filename(), "rt-00120001.xml");
}

TEST_F(EniRevisionMatch, AnotherMajorWordIsNeverTaken) {
  auto devs = eni_devices(net(0x00130000), dir);
  ASSERT_TRUE(devs) << devs.error().to_string();
  EXPECT_EQ((*devs)[0].esi_file, "");  // synthesised from the ENI
  EXPECT_EQ((*devs)[0].device.identity.revision, 0x00130000u);
}

}  // namespace
}  // namespace ecat::esi
