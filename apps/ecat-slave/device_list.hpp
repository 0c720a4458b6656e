// Turns the device options of ecat-slave into device descriptions, in chain order.
#pragma once

#include <string>
#include <vector>

#include "apps/ecat-slave/options.hpp"
#include "common/expected.hpp"
#include "od/device.hpp"

namespace ecat::app {

Expected<std::vector<od::DeviceDescription>, std::string> load_devices(const SlaveProgramOptions& options);

}  // namespace ecat::app
