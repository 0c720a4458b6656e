#include "apps/ecat-slave/pdi_host_setup.hpp"

#include <cstdio>

#include <fmt/format.h>

namespace ecat::app {

Expected<std::unique_ptr<pdi_host::PdiHost>, std::string> open_pdi_host(const SlaveProgramOptions& o,
                                                                       slave::Chain& chain, const Clock& clock) {
  if (o.pdi_host.empty()) return std::unique_ptr<pdi_host::PdiHost>{};
  auto chip = pdi_host::parse_pdi_chip(o.pdi_chip);
  if (!chip) return fail(chip.error());
  // Attaching, leaving and why a firmware was dropped: printed even with
  // --quiet (the firmware's developer needs the reason).
  auto log = [](const std::string& line) { std::fprintf(stderr, "ecat-slave: %s\n", line.c_str()); };
  auto host = pdi_host::PdiHost::open(o.pdi_host, chain[0].esc(), *chip, clock, log);
  if (!host) return fail(host.error());
  if (!o.quiet) {
    std::fprintf(stderr, "ecat-slave: slave 1 (%s) waits for its firmware on %s (%s PDI)\n",
                 chain[0].device().identity.name.c_str(), o.pdi_host.c_str(), pdi_host::describe(*chip));
  }
  return host;
}

}  // namespace ecat::app
