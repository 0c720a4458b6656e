// ENI DC settings (docs/twins.md "ENI DC settings"): Slave/DC of a
// configurator-exported ENI (tests/data/eni/kpierczy-elmo-wheels.xml) is read,
// and for a slave whose dictionary comes from an ESI the ENI's Sync0 cycle and
// shift become the defaults of 1C32h/1C33h:02/:03; the DC activation the ENI's
// PS register InitCmd writes (0980h = 0003h bytes, AssignActivate 0300h) is
// one of the Elmo ESI's OpModes, so no warning; one that is not is warned.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <unistd.h>

#include "esi/eni_devices.hpp"
#include "esi/eni_reader.hpp"

namespace ecat::esi {
namespace {

namespace fs = std::filesystem;

std::string data(const char* rel) { return std::string(ECAT_SOURCE_DIR) + "/tests/data/" + rel; }

std::uint32_t u32(const od::DeviceDescription& d, std::uint16_t index, std::uint8_t sub) {
  const od::Entry* e = d.dictionary.find(index, sub);
  EXPECT_NE(e, nullptr) << std::hex << index << ":" << int(sub);
  if (!e || e->default_value.size() < 4) return 0xFFFFFFFFu;
  const auto& v = e->default_value;
  return std::uint32_t{v[0]} | (std::uint32_t{v[1]} << 8) | (std::uint32_t{v[2]} << 16) | (std::uint32_t{v[3]} << 24);
}

class EniDc : public ::testing::Test {
 protected:
  void SetUp() override {
    // One directory per process: ctest runs each test of this fixture as its
    // own process, side by side.
    dir = fs::path(::testing::TempDir()) / ("eni-dc-esi-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::copy_file(data("esi-vendor/elmo-gold-ecat.xml"), dir / "elmo-gold-ecat.xml");
  }
  void TearDown() override { fs::remove_all(dir); }
  fs::path dir;
};

TEST_F(EniDc, SlaveDcIsRead) {
  std::vector<EsiWarning> w;
  auto net = read_eni(data("eni/kpierczy-elmo-wheels.xml"), &w);
  ASSERT_TRUE(net) << net.error().to_string();
  ASSERT_EQ(net->slaves.size(), 5u);
  EXPECT_FALSE(net->slaves[0].dc);  // the IMU has none
  ASSERT_TRUE(net->slaves[1].dc);
  EXPECT_TRUE(net->slaves[1].dc->reference_clock);
  EXPECT_EQ(net->slaves[1].dc->cycle_time0, 10000000u);
  EXPECT_EQ(net->slaves[1].dc->cycle_time1, 0u);
  EXPECT_EQ(net->slaves[1].dc->shift_time, 0);
  EXPECT_EQ(net->slaves[1].dc->line, 2593);
  ASSERT_TRUE(net->slaves[2].dc);
  EXPECT_FALSE(net->slaves[2].dc->reference_clock);
  for (const auto& x : w) EXPECT_NE(x.element, "DC") << x.message;  // no longer "not used"
}

TEST_F(EniDc, CycleAndShiftBecomeTheSyncParameterDefaults) {
  auto net = read_eni(data("eni/kpierczy-elmo-wheels.xml"));
  ASSERT_TRUE(net) << net.error().to_string();
  net->slaves[1].dc->shift_time = 250000;  // a shift, to see it arrive
  std::vector<EsiWarning> w;
  auto devs = eni_devices(*net, dir, &w);
  ASSERT_TRUE(devs) << devs.error().to_string();
  const od::DeviceDescription& drive = (*devs)[1].device;
  EXPECT_EQ(u32(drive, 0x1C32, 2), 10000000u);
  EXPECT_EQ(u32(drive, 0x1C33, 2), 10000000u);
  EXPECT_EQ(u32(drive, 0x1C32, 3), 250000u);
  EXPECT_EQ(u32((*devs)[2].device, 0x1C32, 3), 0u);
  for (const auto& x : w) EXPECT_EQ(x.message.find("AssignActivate"), std::string::npos) << x.message;
}

TEST_F(EniDc, AnAssignActivateTheEsiDoesNotHaveIsWarned) {
  auto net = read_eni(data("eni/kpierczy-elmo-wheels.xml"));
  ASSERT_TRUE(net) << net.error().to_string();
  for (auto& c : net->slaves[1].init_cmds) {
    if (c.ado == 0x0980 && c.data == od::Value{0x00, 0x03}) c.data = {0x00, 0x07};
  }
  std::vector<EsiWarning> w;
  auto devs = eni_devices(*net, dir, &w);
  ASSERT_TRUE(devs) << devs.error().to_string();
  bool seen = false;
  for (const auto& x : w) {
    if (x.line == 2593 && x.message == "AssignActivate #x0700 (the 0980h InitCmd) is none of the ESI's OpModes") seen = true;
  }
  EXPECT_TRUE(seen);
}

}  // namespace
}  // namespace ecat::esi
