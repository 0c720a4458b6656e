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
#include "slave/lane_judge.hpp"

namespace ecat::app {

Expected<std::unique_ptr<slave::Chain>, std::string> make_chain(const SlaveProgramOptions& options,
                                                               std::vector<od::DeviceDescription> devices,
                                                               const Clock& clock);

// --firmware-threads: starts the helpers (slave::Chain::set_firmware_threads);
// warns on stderr (unless quiet) when there are more threads than CPUs this
// process may run on - spinning helpers would then take the loop's CPU.
// With auto, a `judge_clock` (a live run) and --firmware-threads-recheck
// above 0: when the chain and the host allow two threads, the helper is
// started whatever the round trip says, the split paused if it says one,
// and the judge that decides again while the chain runs is returned (else
// null; slave/lane_judge.hpp).
Expected<std::unique_ptr<slave::LaneJudge>, std::string> start_firmware_threads(slave::Chain& chain,
                                                                                const SlaveProgramOptions& options,
                                                                                const Clock* judge_clock = nullptr);

// One line per slave plus the chain counters, as --stats and SIGUSR1 print
// them; with a judge, what it found last.
std::string format_stats(const slave::Chain& chain, const slave::LaneJudge* judge = nullptr);

}  // namespace ecat::app
