#include "apps/ecat-slave/control_setup.hpp"

#include <cstdio>

namespace ecat::app {

Expected<std::unique_ptr<ControlPlane>, std::string> open_control(const SlaveProgramOptions& o, slave::Chain& chain,
                                                                  const Clock& clock, slave::FaultCatalogue& faults) {
  if (o.control.empty() && o.scenario.empty()) return std::unique_ptr<ControlPlane>{};
  auto plane = std::make_unique<ControlPlane>();
  plane->handler = std::make_unique<control::RequestHandler>(chain, clock, plane->events, &faults);
  if (!o.scenario.empty()) {
    auto sc = scenario::load_scenario(o.scenario);
    if (!sc) return fail(sc.error());
    // The server samples the chain for events when there is one; else the runner does.
    plane->scenario = std::make_unique<scenario::ScenarioRunner>(std::move(*sc), *plane->handler, o.control.empty());
    if (!o.quiet) {
      std::fprintf(stderr, "ecat-slave: scenario %s (%zu steps)\n", plane->scenario->scenario().name.c_str(),
                   plane->scenario->scenario().steps.size());
    }
  }
  if (o.control.empty()) return plane;
  auto server = control::ControlServer::open(o.control, *plane->handler);
  if (!server) return fail(server.error());
  plane->server = std::move(*server);
  if (!plane->server->loopback_only()) {
    // Printed even with --quiet, as --udp's: whoever reaches it controls every slave.
    std::fprintf(stderr,
                 "ecat-slave: warning: control %s is reachable unauthenticated from the network: whoever reaches it "
                 "reads and writes every object and engages faults (docs/control.md)\n",
                 plane->server->address().c_str());
  }
  if (!o.quiet) std::fprintf(stderr, "ecat-slave: control on %s\n", plane->server->address().c_str());
  return plane;
}

}  // namespace ecat::app
