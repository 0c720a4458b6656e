// Turns the device options of ecat-slave into device descriptions, in chain order.
#pragma once

#include <string>
#include <vector>

#include "apps/ecat-slave/options.hpp"
#include "common/expected.hpp"
#include "esi/eni_reader.hpp"
#include "slave/eoe_init_check.hpp"
#include "od/device.hpp"

namespace ecat::app {

// With --eni, also fills options.eoe_init from the ENI's EoE InitCmds.
Expected<std::vector<od::DeviceDescription>, std::string> load_devices(SlaveProgramOptions& options);

// The checks of one ENI slave's EoE InitCmds (those with a Set IP Parameter
// request on IP, PS or SO), named "FILE:LINE[:COLUMN] (TRANSITION)".
std::vector<slave::EoeInitExpectation> eoe_init_expectations(const esi::EniSlave& slave, const std::string& file);

}  // namespace ecat::app
