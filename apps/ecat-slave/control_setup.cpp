#include "apps/ecat-slave/control_setup.hpp"

#include <cstdio>
#include <filesystem>
#include <system_error>

#include "web/static_files.hpp"

namespace ecat::app {
namespace {

// The directory of the running program (for share/ecatslave/www beside it).
std::string program_dir() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(".") : exe.parent_path().string();
}

Expected<void, std::string> open_web(const SlaveProgramOptions& o, ControlPlane& plane) {
  web::WebOptions wo;
  wo.listen = o.http;
  wo.www_dir = web::find_www_dir(o.http_root, program_dir());
  // The chain is sampled for events once: by the control server, else the scenario runner, else here.
  wo.sample_events = plane.server == nullptr && plane.scenario == nullptr;
  auto server = web::WebServer::open(wo, *plane.handler);
  if (!server) return fail(server.error());
  plane.web = std::move(*server);
  if (!plane.web->loopback_only()) {
    // Printed even with --quiet, as --udp's and --control's.
    std::fprintf(stderr,
                 "ecat-slave: warning: HTTP %s is reachable unauthenticated from the network: whoever reaches it "
                 "reads and writes every object and engages faults (docs/security.md)\n",
                 plane.web->url().c_str());
  }
  if (!o.quiet) std::fprintf(stderr, "ecat-slave: web view on %s (page files %s)\n", plane.web->url().c_str(), wo.www_dir.c_str());
  return {};
}

}  // namespace

Expected<std::unique_ptr<ControlPlane>, std::string> open_control(const SlaveProgramOptions& o, slave::Chain& chain,
                                                                  const Clock& clock, slave::FaultCatalogue& faults) {
  if (o.control.empty() && o.scenario.empty() && o.http.empty()) return std::unique_ptr<ControlPlane>{};
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
  if (o.control.empty()) {
    if (!o.http.empty()) {
      if (auto ok = open_web(o, *plane); !ok) return fail(ok.error());
    }
    return plane;
  }
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
  if (!o.http.empty()) {
    if (auto ok = open_web(o, *plane); !ok) return fail(ok.error());
  }
  return plane;
}

}  // namespace ecat::app
