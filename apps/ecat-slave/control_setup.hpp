// ecat-slave --control: the control interface (docs/control.md) on the
// running chain - the request handler, its event queue and the socket
// server the live loop services on its tick.
#pragma once

#include <memory>
#include <string>

#include "apps/ecat-slave/options.hpp"
#include "common/expected.hpp"
#include "control/control_server.hpp"
#include "control/event_queue.hpp"
#include "control/request_handler.hpp"
#include "scenario/scenario_runner.hpp"
#include "web/web_server.hpp"

namespace ecat::slave {
class Chain;
class FaultCatalogue;
}  // namespace ecat::slave

namespace ecat::app {

// Exit status of ecat-slave when its --scenario failed (0 when it passed).
inline constexpr int kExitScenarioFailed = 3;

struct ControlPlane {
  control::EventQueue events;
  std::unique_ptr<control::RequestHandler> handler;
  std::unique_ptr<control::ControlServer> server;      // --control
  std::unique_ptr<scenario::ScenarioRunner> scenario;  // --scenario
  std::unique_ptr<web::WebServer> web;                 // --http
};

// Null without --control, --http and --scenario; an error names the option and why
// it cannot listen, or the scenario file's line and what is wrong there.
Expected<std::unique_ptr<ControlPlane>, std::string> open_control(const SlaveProgramOptions& o, slave::Chain& chain,
                                                                  const Clock& clock, slave::FaultCatalogue& faults);

}  // namespace ecat::app
