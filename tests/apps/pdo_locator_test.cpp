// ecat-master's PDO locator (apps/ecat-master/pdo_locator.cpp) against
// in-process virtual slaves: where each mapped object lies in the slave's
// outputs and inputs, read from the PDO assignment (1C12h/1C13h) and mapping
// objects; a side whose assignment object does not exist (abort 06020000,
// a device without process data there) has no PDOs, not an error.
#include "apps/ecat-master/pdo_locator.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "esi/device_loader.hpp"
#include "esi/esi_writer_device_xml.hpp"
#include "tests/master/in_process_bus.hpp"

namespace ecat::app {
namespace {

using master::test::InProcessBus;
using master::test::device_path;

constexpr std::uint16_t kTxPdoAssign = 0x1C13;
constexpr std::size_t kInputsSm = 3;
constexpr std::uint16_t kControlword = 0x6040;
constexpr std::uint16_t kStatusword = 0x6041;

Expected<PdoLocator, std::string> locate(const std::string& file) {
  InProcessBus bus;
  EXPECT_TRUE(bus.add(file));
  master::Master m(bus.transport, bus.clock);
  EXPECT_EQ(m.scan().value_or(0), 1u);
  EXPECT_TRUE(m.configure_mailbox(0).has_value());
  auto st = m.request_state(0, master::AlState::PreOp);
  EXPECT_TRUE(st && st->is(master::AlState::PreOp));
  master::CoeClient coe(m, 0);
  return PdoLocator::read(coe);
}

TEST(PdoLocator, ObjectsOfTheDefaultServoAtTheirBytes) {
  auto l = locate(device_path("generic-servo.xml"));
  ASSERT_TRUE(l) << l.error();
  EXPECT_EQ(l->output_byte(kControlword), 0u);  // 1600h starts with the controlword
  EXPECT_EQ(l->input_byte(kStatusword), 0u);    // 1A00h starts with the statusword
  EXPECT_FALSE(l->output_byte(kStatusword).has_value());
}

// The default servo without TxPDOs, inputs SM and 1C13h: its inputs are
// empty, its outputs are found as before.
TEST(PdoLocator, MissingAssignmentObjectMeansNoPdos) {
  auto d = esi::load_device_file(device_path("generic-servo.xml"));
  ASSERT_TRUE(d) << d.error().to_string();
  for (const auto& p : d->tx_pdos) d->dictionary.erase(p.index);
  d->tx_pdos.clear();
  ASSERT_TRUE(d->dictionary.erase(kTxPdoAssign));
  ASSERT_EQ(d->sync_managers.size(), kInputsSm + 1u);
  d->sync_managers.pop_back();  // no inputs SM: nothing brings 1C13h back
  const std::string file = std::string(ECAT_BINARY_DIR) + "/test-output/pdo_locator_no_1c13.xml";
  std::filesystem::create_directories(std::filesystem::path(file).parent_path());
  std::ofstream(file) << esi::write_device_xml(*d);
  auto l = locate(file);
  ASSERT_TRUE(l) << l.error();
  EXPECT_TRUE(l->inputs.empty());
  EXPECT_EQ(l->output_byte(kControlword), 0u);
}

}  // namespace
}  // namespace ecat::app
