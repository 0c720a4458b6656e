// The seed drives as a chain in one process: each is scanned, its SII read,
// its PDOs read over SDO, and the line reaches Op with the right WKC.
#include <gtest/gtest.h>

#include <string>

#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

od::DeviceDescription load(const std::string& name) {
  auto d = esi::load_device_file(std::string(ECAT_SOURCE_DIR) + "/xml/devices/" + name);
  if (!d) throw std::runtime_error(d.error().to_string());
  return std::move(*d);
}

TEST(InProcessStack, SeedDrivesWithLrwReachOpAsAChain) {
  InProcess p;
  for (const char* f : {"simtach-rse.xml", "welcon-servo.xml", "leadshine-isv2-can.xml", "generic-servo.xml"}) {
    p.add(load(f));
  }
  ASSERT_EQ(p.bring_up(), "");
  ASSERT_EQ(p.master.slave_count(), 4u);
  // Every slave has outputs and inputs: LRW counts 3 at each.
  EXPECT_EQ(p.master.expected_wkc(), 12);
  for (int c = 0; c < 100; ++c) {
    auto r = p.cycle_once(std::chrono::milliseconds(1));
    ASSERT_TRUE(r);
    ASSERT_EQ(r->wkc, 12) << "cycle " << c;
  }
  for (std::size_t i = 0; i < 4; ++i) {
    auto st = p.master.read_al_status(i);
    ASSERT_TRUE(st);
    EXPECT_EQ(st->raw, 0x0008) << "slave " << i;
  }
  // Identity from the SII matches each device file.
  EXPECT_EQ(p.master.slave(0).sii.product_code, p.chain[0].device().identity.product_code);
  EXPECT_EQ(p.master.slave(3).sii.device_name(), p.chain[3].device().identity.name);
}

}  // namespace
}  // namespace ecat::test
