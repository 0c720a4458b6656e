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

// --firmware-threads: starts the helpers (slave::Chain::set_firmware_threads);
// warns on stderr (unless quiet) when there are more threads than CPUs this
// process may run on - spinning helpers would then take the loop's CPU.
Expected<void, std::string> start_firmware_threads(slave::Chain& chain, const SlaveProgramOptions& options);

// One line per slave plus the chain counters, as --stats and SIGUSR1 print them.
std::string format_stats(const slave::Chain& chain);

}  // namespace ecat::app
