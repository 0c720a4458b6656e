// The control interface's request handler (issue 26 item 1, docs/control.md):
// one JSON request in, one JSON reply out, on a slave::Chain, independent of
// the transport - the socket server (control_server.hpp) feeds it lines, an
// HTTP front (issue 27) can feed it request bodies. Bad input (unknown
// slave, object, fault; a malformed message; a value of the wrong type or
// out of range) gets an error reply and changes nothing.
//
//   request:  {"id": 7, "cmd": "read", "slave": 0, "index": "0x6041", "subindex": 0}
//   reply:    {"id": 7, "result": {"index": 24641, ..., "value": 592, "hex": "5002"}}
//   error:    {"id": 7, "error": {"code": "unknown_slave", "message": "slave 3: no such slave (chain has 2)"}}
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "common/clock.hpp"
#include "control/event_queue.hpp"

namespace ecat::slave {
class Chain;
class FaultCatalogue;
}  // namespace ecat::slave

namespace ecat::control {

class SimulatedRun;

// The protocol's version, in "hello"'s reply; a change that breaks a client raises it.
inline constexpr int kProtocolVersion = 1;

class RequestHandler {
 public:
  // Most events one "events" request returns, and most cycles one "step" runs.
  static constexpr std::size_t kMaxEventsPerReply = 10000;
  static constexpr std::uint64_t kMaxStepCycles = 10'000'000;

  // `faults` (may be null: the fault commands then reply "no_faults") gets
  // an observer that pushes "fault_engaged"/"fault_cleared" events; `sim`
  // (may be null: "not_simulated") is what pause/step/run act on. All must
  // outlive the handler.
  RequestHandler(slave::Chain& chain, const Clock& clock, EventQueue& events, slave::FaultCatalogue* faults = nullptr,
                 SimulatedRun* sim = nullptr);
  ~RequestHandler();
  RequestHandler(const RequestHandler&) = delete;
  RequestHandler& operator=(const RequestHandler&) = delete;

  // One request line (JSON text) -> one reply (JSON text, no newline).
  std::string handle_line(std::string_view line);
  nlohmann::json handle(const nlohmann::json& request);

  EventQueue& events() noexcept { return events_; }
  slave::Chain& chain() noexcept { return chain_; }
  const Clock& clock() const noexcept { return clock_; }
  // Whether the "faults" command would list anything.
  bool faults_engaged() const;

 private:
  struct Command;
  nlohmann::json dispatch(const nlohmann::json& request);

  nlohmann::json hello(const nlohmann::json& r);
  nlohmann::json network(const nlohmann::json& r);
  nlohmann::json slave(const nlohmann::json& r);
  nlohmann::json read(const nlohmann::json& r);
  nlohmann::json register_read(const nlohmann::json& r);
  nlohmann::json write(const nlohmann::json& r);
  nlohmann::json pdo(const nlohmann::json& r);
  nlohmann::json events_since(const nlohmann::json& r);
  nlohmann::json fault_kinds(const nlohmann::json& r);
  nlohmann::json fault_engage(const nlohmann::json& r);
  nlohmann::json fault_clear(const nlohmann::json& r);
  nlohmann::json faults_list(const nlohmann::json& r);
  nlohmann::json pause(const nlohmann::json& r);
  nlohmann::json run(const nlohmann::json& r);
  nlohmann::json step(const nlohmann::json& r);
  nlohmann::json time(const nlohmann::json& r);
  nlohmann::json streaming_only(const nlohmann::json& r);

  slave::FaultCatalogue& need_faults();
  SimulatedRun& need_sim();

  slave::Chain& chain_;
  const Clock& clock_;
  EventQueue& events_;
  slave::FaultCatalogue* faults_;
  SimulatedRun* sim_;
};

}  // namespace ecat::control
