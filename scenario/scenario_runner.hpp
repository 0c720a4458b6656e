// Runs a scenario (scenario.hpp) against a network through its control
// interface: `do` steps are requests to the control::RequestHandler, events
// come from its EventQueue, values from its "read" command - the same
// mechanism a test script or the Python package uses (docs/scenarios.md).
// The owner's loop calls poll(now, frames) often (ecat-slave: every idle
// pass, so about once per master cycle; a simulated run: every cycle); a
// value expectation is read at each poll, events are sampled every 10 ms
// (by the runner's own EventWatcher when no ControlServer samples them).
// A step that fails ends the scenario: the steps after it are skipped.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/clock.hpp"
#include "control/control_server.hpp"
#include "control/event_watcher.hpp"
#include "control/request_handler.hpp"
#include "scenario/scenario.hpp"

namespace ecat::scenario {

struct StepResult {
  enum class Status { Pending, Passed, Failed, Skipped };
  Status status = Status::Pending;
  Nanoseconds started{0};  // since the scenario started: when the step became current
  Nanoseconds ended{0};
  std::string message;     // why it failed, or what it saw
};
std::string_view describe(StepResult::Status s) noexcept;

class ScenarioRunner {
 public:
  // Events are sampled as often as a ControlServer samples them.
  static constexpr Nanoseconds kSamplePeriod = control::ControlServer::kTick;
  static constexpr Nanoseconds kValuePeriod = std::chrono::microseconds(250);

  // `sample_events`: the runner samples the chain for events itself (no
  // ControlServer on this handler does).
  ScenarioRunner(Scenario scenario, control::RequestHandler& handler, bool sample_events);

  // Moves the scenario on; `frames` counts the master's frames so far.
  void poll(Nanoseconds now, std::uint64_t frames);
  // Ends a scenario that is not done (the program is stopping): the
  // current step fails with `why`, the rest are skipped.
  void abort(Nanoseconds now, const std::string& why);

  bool done() const noexcept { return current_ >= scenario_.steps.size(); }
  bool passed() const noexcept;
  // How long the owner may wait before poll() has work (0 while a value is watched).
  Nanoseconds until_due(Nanoseconds now) const noexcept;

  const Scenario& scenario() const noexcept { return scenario_; }
  const std::vector<StepResult>& results() const noexcept { return results_; }
  Nanoseconds elapsed() const noexcept { return last_ - start_; }
  // One line per step and a last line: "scenario NAME: passed (N steps, T)".
  std::string summary() const;

 private:
  bool triggered(const Step& s, Nanoseconds now, std::uint64_t frames);
  // Runs or checks the current step; true when it is over (passed or failed).
  bool act(const Step& s, Nanoseconds now);
  // The first event from `*cursor` that `m` matches (the cursor moves past what was looked at).
  std::optional<nlohmann::json> next_event(const Match& m, std::uint64_t* cursor);
  // Whether the value of `m` holds now; `seen` gets the value read, or the error.
  bool value_holds(const Match& m, std::string* seen, bool* error);
  nlohmann::json fill_in(const nlohmann::json& request, std::string* missing) const;
  // Ends the current step; the next one looks at events from `cursor` (default: from now).
  void finish(StepResult::Status status, Nanoseconds now, std::string message,
              std::optional<std::uint64_t> cursor = std::nullopt);

  Scenario scenario_;
  control::RequestHandler& handler_;
  std::unique_ptr<control::EventWatcher> watcher_;
  std::vector<StepResult> results_;
  std::map<std::string, nlohmann::json> saved_;
  std::size_t current_ = 0;
  bool started_ = false;
  bool step_triggered_ = false;
  Nanoseconds start_{0};
  Nanoseconds last_{0};
  Nanoseconds next_sample_{0};
  Nanoseconds step_began_{0};     // when the previous step ended
  Nanoseconds window_began_{0};   // when the current step's trigger fired
  std::uint64_t step_frames_ = 0; // frames when the previous step ended
  std::uint64_t trigger_cursor_ = 0;
  std::uint64_t window_cursor_ = 0;
  std::string last_value_;        // of the current value match, for the failure message
};

}  // namespace ecat::scenario
