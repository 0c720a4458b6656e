// Issue 16 item 5: slaves built from one description hold one SII image
// (slave/shared_eeprom.hpp, esc::EepromImage), and a word the master writes
// into one slave's EEPROM reaches that slave's image only.
#include <gtest/gtest.h>

#include "esi/device_loader.hpp"
#include "esi/sii_writer.hpp"
#include "slave/esc_setup.hpp"
#include "slave/shared_eeprom.hpp"
#include "slave/virtual_slave.hpp"

namespace ecat::test {
namespace {

TEST(SharedEeprom, EqualImagesShareOneCopy) {
  const std::vector<std::uint8_t> bytes{1, 2, 3, 4};
  esc::EepromImage a = slave::shared_eeprom_image(bytes);
  esc::EepromImage b = slave::shared_eeprom_image(bytes);
  esc::EepromImage other = slave::shared_eeprom_image({1, 2, 3, 5});
  EXPECT_EQ(a.data(), b.data());
  EXPECT_NE(a.data(), other.data());
  EXPECT_TRUE(a.shared());
  // A write copies: b and the registry keep the old bytes.
  a.mutable_data()[3] = 9;
  EXPECT_NE(a.data(), b.data());
  EXPECT_EQ(a[3], 9);
  EXPECT_EQ(b[3], 4);
  esc::EepromImage c = slave::shared_eeprom_image(bytes);
  EXPECT_EQ(c.data(), b.data());
  EXPECT_EQ(c[3], 4);
  // The last holder of a registered image still copies before writing:
  // the registry may hand the same bytes out again meanwhile.
  esc::EepromImage only = slave::shared_eeprom_image({7, 7});
  const std::uint8_t* registered = only.data();
  only.mutable_data()[0] = 8;
  EXPECT_NE(only.data(), registered);
  EXPECT_EQ(slave::shared_eeprom_image({7, 7})[0], 7);
}

TEST(SharedEeprom, SlavesOfOneDescriptionShareTheirImage) {
  auto device = esi::load_device_file(std::string(ECAT_SOURCE_DIR) + "/xml/devices/generic-servo.xml");
  ASSERT_TRUE(device) << device.error().to_string();
  const auto expected = esi::write_sii(*device);
  ASSERT_TRUE(expected);
  auto shared = std::make_shared<const od::DeviceDescription>(std::move(*device));
  ManualClock clock;
  auto s1 = slave::VirtualSlave::create(shared, clock, slave::SlaveOptions{});
  auto s2 = slave::VirtualSlave::create(shared, clock, slave::SlaveOptions{});
  ASSERT_TRUE(s1);
  ASSERT_TRUE(s2);
  const esc::EepromImage& i1 = (*s1)->esc().config().sii;
  const esc::EepromImage& i2 = (*s2)->esc().config().sii;
  EXPECT_EQ(i1.data(), i2.data());
  ASSERT_EQ(i1.size(), expected->size());
  EXPECT_TRUE(std::equal(expected->begin(), expected->end(), i1.data()));
}

}  // namespace
}  // namespace ecat::test
