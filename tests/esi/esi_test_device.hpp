// A small CiA 402 servo built in code, shared by the ESI/SII/C++ writer tests
// so they do not depend on the device-file loader.
#pragma once

#include "od/device.hpp"

namespace ecat::esi::test {

od::DeviceDescription make_test_device();

}  // namespace ecat::esi::test
