// ecat-slave --pdi-host: the PDI host on the first slave of the chain
// (docs/pdi-host.md), serviced by the live loop.
#pragma once

#include <memory>
#include <string>

#include "apps/ecat-slave/options.hpp"
#include "common/clock.hpp"
#include "common/expected.hpp"
#include "pdi_host/pdi_host.hpp"
#include "slave/chain.hpp"

namespace ecat::app {

// Descriptors the host adds to the live loop's wait.
inline constexpr std::size_t kPdiHostFds = 2;

// Null without --pdi-host; an error says why it cannot listen.
Expected<std::unique_ptr<pdi_host::PdiHost>, std::string> open_pdi_host(const SlaveProgramOptions& o,
                                                                       slave::Chain& chain, const Clock& clock);

}  // namespace ecat::app
