// A scenario file (issue 26 item 3, docs/scenarios.md): steps run against a
// virtual network through its control interface, triggered by time, frame
// count or an event, and expectations on what the master then does.
//
//   name: drive fault and recovery
//   timeout: 60s
//   steps:
//     - name: the master brings the drive to Op
//       expect: {type: al_state, slave: 0, to: OP}
//       within: 30s
//     - after: 500ms
//       do: {cmd: fault_engage, kind: drive_fault, slave: 0, params: {code: 0x2310}}
//       save: overcurrent
//     - expect: {read: {slave: 0, index: 0x6041}, mask: 0x004F, equals: 0x0008}
//       within: 100ms
//     - after: 1s
//       do: {cmd: fault_clear, fault: ${overcurrent.fault}}
//
// A step has at most one trigger (`after` the previous step ended, `at` a
// time from the start, `after_frames` frames of the master since the
// previous step, `when` an event) and at most one of `do` (a control
// request, the same JSON as docs/control.md), `expect` (an event or a value
// that must come `within` a time), `expect_not` (an event or value that
// must not come `for` a time). Loading checks the whole file and reports the
// first problem as FILE:LINE:COLUMN: what is wrong.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/clock.hpp"
#include "common/expected.hpp"

namespace ecat::scenario {

inline constexpr Nanoseconds kDefaultTimeout = std::chrono::seconds(60);
inline constexpr Nanoseconds kDefaultWithin = std::chrono::seconds(10);

// What an `expect`, `expect_not` or `when` looks for.
struct Match {
  enum class Kind { Event, Value };
  Kind kind = Kind::Event;
  // Event: the fields an event must have ("type" and any of its fields; a
  // list means any of its values; strings compare without case).
  nlohmann::json event;
  // Value: a `read` request (slave, index, subindex) and what its value must be:
  // `equals` (after `mask`, when given), or within [`min`, `max`].
  nlohmann::json read;
  std::optional<std::uint64_t> mask;
  nlohmann::json equals;
  std::optional<double> min;
  std::optional<double> max;
};

struct Step {
  std::string name;  // given, or made from what the step does
  int line = 0;      // 1-based, in the file
  // The trigger (none: at once).
  std::optional<Nanoseconds> after;
  std::optional<Nanoseconds> at;
  std::optional<std::uint64_t> after_frames;
  std::optional<Match> when;
  // What the step does once triggered.
  enum class Action { None, Do, Expect, ExpectNot };
  Action action = Action::None;
  nlohmann::json request;   // Do: a control request; "${name.field}" strings filled in when it runs
  std::string save;         // Do: keep the result under this name
  Match match;              // Expect / ExpectNot
  Nanoseconds window{0};    // Expect: `within`; ExpectNot: `for`
};

struct Scenario {
  std::string name;
  std::string file;
  Nanoseconds timeout = kDefaultTimeout;
  std::vector<Step> steps;
};

// Parses a scenario from YAML text; `file` names it in error messages.
Expected<Scenario, std::string> parse_scenario(std::string_view text, std::string_view file);
Expected<Scenario, std::string> load_scenario(const std::string& path);

// "250ms", "2s", "1.5s", "500us", "100ns", "1min"; nothing else.
Expected<Nanoseconds, std::string> parse_duration(std::string_view text);
std::string format_duration(Nanoseconds d);

}  // namespace ecat::scenario
