// Builds the slave chain that both runners use, from the loaded devices and
// the per-slave options (state files, DC oscillator error).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "apps/ecat-slave/options.hpp"
#include "common/clock.hpp"
#include "common/expected.hpp"
#include "od/device.hpp"
#include "slave/chain.hpp"

namespace ecat::app {

Expected<std::unique_ptr<slave::Chain>, std::string> make_chain(const SlaveProgramOptions& options,
                                                               std::vector<od::DeviceDescription> devices,
                                                               const Clock& clock);

// One line per slave plus the chain counters, as --stats and SIGUSR1 print them.
std::string format_stats(const slave::Chain& chain);

}  // namespace ecat::app
