// The two ways ecat-slave runs a chain: live on a transport (raw Ethernet or
// UDP) until SIGINT/SIGTERM, or replaying a pcap capture. Both return the
// process exit status.
#pragma once

#include <vector>

#include "apps/ecat-slave/options.hpp"
#include "od/device.hpp"

namespace ecat::app {

int run_live(const SlaveProgramOptions& options, std::vector<od::DeviceDescription> devices);
int run_pcap(const SlaveProgramOptions& options, std::vector<od::DeviceDescription> devices);
// The firmware of the first device on a real ESC behind spidev (--pdi).
int run_spi(const SlaveProgramOptions& options, std::vector<od::DeviceDescription> devices);

}  // namespace ecat::app
