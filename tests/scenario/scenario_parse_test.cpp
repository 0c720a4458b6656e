// Scenario files (scenario/scenario.hpp, docs/scenarios.md): what a file
// says becomes exact steps, and every mistake is reported with the file,
// line and column where it is.
#include <gtest/gtest.h>

#include <filesystem>

#include "scenario/scenario.hpp"

namespace ecat::scenario {
namespace {

using nlohmann::json;
using std::chrono::milliseconds;
using std::chrono::seconds;

constexpr const char* kDriveFault = R"(name: drive fault
timeout: 20s
steps:
  - name: in Op
    expect: {type: al_state, slave: 0, to: [OP, SAFEOP]}
    within: 5s
  - after: 500ms
    do: {cmd: fault_engage, kind: drive_fault, slave: 0, params: {code: 0x2310}}
    save: oc
  - expect: {read: {slave: 0, index: 0x6041}, mask: 0x4F, equals: 0x08}
    within: 100ms
  - after_frames: 10
    do: {cmd: fault_clear, fault: "${oc.fault}", note: '0x10'}
  - when: {type: emergency, slave: 0, error_code: 0}
  - at: 3s
    expect_not: {type: al_state, slave: 0}
    for: 1.5s
)";

TEST(ScenarioParse, StepsAsWritten) {
  auto s = parse_scenario(kDriveFault, "drive.yaml");
  ASSERT_TRUE(s) << s.error();
  EXPECT_EQ(s->name, "drive fault");
  EXPECT_EQ(s->timeout, seconds(20));
  ASSERT_EQ(s->steps.size(), 6u);
  const Step& in_op = s->steps[0];
  EXPECT_EQ(in_op.name, "in Op");
  EXPECT_EQ(in_op.line, 4);
  EXPECT_EQ(in_op.action, Step::Action::Expect);
  EXPECT_EQ(in_op.match.kind, Match::Kind::Event);
  EXPECT_EQ(in_op.match.event, json::parse(R"({"type":"al_state","slave":0,"to":["OP","SAFEOP"]})"));
  EXPECT_EQ(in_op.window, seconds(5));
  const Step& engage = s->steps[1];
  EXPECT_EQ(engage.name, "step 2");
  EXPECT_EQ(engage.after, milliseconds(500));
  EXPECT_EQ(engage.action, Step::Action::Do);
  // 0x2310 is the integer 8976, as the control interface takes it.
  EXPECT_EQ(engage.request,
            json::parse(R"({"cmd":"fault_engage","kind":"drive_fault","slave":0,"params":{"code":8976}})"));
  EXPECT_EQ(engage.save, "oc");
  const Step& fault = s->steps[2];
  EXPECT_EQ(fault.match.kind, Match::Kind::Value);
  EXPECT_EQ(fault.match.read, json::parse(R"({"cmd":"read","slave":0,"index":24641})"));
  EXPECT_EQ(fault.match.mask, 0x4Fu);
  EXPECT_EQ(fault.match.equals, 8);
  EXPECT_EQ(fault.window, milliseconds(100));
  // A quoted scalar stays a string ('0x10'), a plain one is read as a number.
  EXPECT_EQ(s->steps[3].after_frames, 10u);
  EXPECT_EQ(s->steps[3].request["note"], "0x10");
  EXPECT_EQ(s->steps[3].request["fault"], "${oc.fault}");
  EXPECT_EQ(s->steps[4].action, Step::Action::None);
  ASSERT_TRUE(s->steps[4].when);
  EXPECT_EQ(s->steps[5].at, seconds(3));
  EXPECT_EQ(s->steps[5].action, Step::Action::ExpectNot);
  EXPECT_EQ(s->steps[5].window, milliseconds(1500));
}

TEST(ScenarioParse, Durations) {
  EXPECT_EQ(*parse_duration("250ms"), milliseconds(250));
  EXPECT_EQ(*parse_duration("2s"), seconds(2));
  EXPECT_EQ(*parse_duration("1.5s"), milliseconds(1500));
  EXPECT_EQ(*parse_duration("500us"), std::chrono::microseconds(500));
  EXPECT_EQ(*parse_duration("100ns"), Nanoseconds(100));
  EXPECT_EQ(*parse_duration("2min"), seconds(120));
  EXPECT_FALSE(parse_duration("2"));
  EXPECT_FALSE(parse_duration("s"));
  EXPECT_FALSE(parse_duration("-1s"));
  EXPECT_FALSE(parse_duration("1h"));
  EXPECT_EQ(parse_duration("2").error(), "'2' is not a duration (a number and one of ns, us, ms, s, min: 250ms, 2s)");
  EXPECT_EQ(format_duration(milliseconds(1500)), "1.500 s");
  EXPECT_EQ(format_duration(milliseconds(100)), "100 ms");
}

std::string error_of(const char* text) {
  auto s = parse_scenario(text, "f.yaml");
  return s ? std::string("parsed") : s.error();
}

TEST(ScenarioParse, MistakesNameTheirPlace) {
  EXPECT_EQ(error_of("steps:\n  - afterr: 1s\n    do: {cmd: hello}\n"),
            "f.yaml:2:5: unknown key 'afterr' in a step (known: name, after, at, after_frames, when, do, save, "
            "expect, expect_not, within, for)");
  EXPECT_EQ(error_of("steps:\n  - after: 10\n    do: {cmd: hello}\n"),
            "f.yaml:2:12: 'after': '10' is not a duration (a number and one of ns, us, ms, s, min: 250ms, 2s)");
  EXPECT_EQ(error_of("steps:\n  - after: 1s\n    at: 2s\n    do: {cmd: hello}\n"),
            "f.yaml:2:5: a step has one trigger at most (after, at, after_frames or when)");
  EXPECT_EQ(error_of("steps:\n  - expect: {type: al_stat, slave: 0}\n"),
            "f.yaml:2:20: unknown event type 'al_stat' (known: al_control, al_state, link, sdo_write, emergency, "
            "fault_engaged, fault_cleared, events_lost)");
  EXPECT_EQ(error_of("steps:\n  - do: {kind: link_cut}\n"),
            "f.yaml:2:9: 'do' must be a control request with 'cmd' (docs/control.md)");
  EXPECT_EQ(error_of("steps:\n  - expect_not: {type: link}\n"),
            "f.yaml:2:5: 'expect_not' needs 'for' (how long it must not happen)");
  EXPECT_EQ(error_of("steps:\n  - expect: {read: {slave: 0}, equals: 1}\n"),
            "f.yaml:2:20: 'read' needs slave and either index (an object) or register (an ESC register)");
  EXPECT_EQ(error_of("steps:\n  - expect: {read: {slave: 0, index: 1, register: 2}, equals: 1}\n"),
            "f.yaml:2:20: 'read' needs slave and either index (an object) or register (an ESC register)");
  EXPECT_EQ(error_of("steps:\n  - expect: {read: {slave: 0, index: 0x6041}}\n"),
            "f.yaml:2:13: a value match needs 'equals', 'min' or 'max'");
  EXPECT_EQ(error_of("steps:\n  - do: {cmd: hello}\n    within: 1s\n"), "f.yaml:3:13: 'within' goes with 'expect'");
  EXPECT_EQ(error_of("steps:\n  - name: nothing\n"),
            "f.yaml:2:5: a step needs a trigger or one of do, expect, expect_not");
  EXPECT_EQ(error_of("name: x\n"), "f.yaml:1:1: 'steps' must be a list of at least one step");
  EXPECT_EQ(error_of("name: x\nstep: []\n"),
            "f.yaml:2:1: unknown key 'step' in the scenario (known: name, timeout, steps)");
  // YAML syntax: yaml-cpp's message at its place.
  EXPECT_EQ(error_of("steps:\n  - do: {cmd: hello\n"), "f.yaml:3:1: end of map flow not found");
  EXPECT_EQ(parse_scenario("x", "f.yaml").error(), "f.yaml:1:1: a scenario is a map with name, timeout and steps");
}

TEST(ScenarioParse, MissingFile) {
  auto s = load_scenario("/nonexistent/scenario.yaml");
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error(), "/nonexistent/scenario.yaml: cannot open the scenario file");
}

// Every example that ships, the SOEM variants too (e2e_soem_scenarios.sh
// runs those only where SOEM's binaries are), loads without an error.
TEST(ScenarioParse, EveryShippedExampleLoads) {
  const std::filesystem::path dir = std::filesystem::path(ECAT_SOURCE_DIR) / "examples" / "scenarios";
  std::size_t files = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    if (e.path().extension() != ".yaml") continue;
    ++files;
    auto s = load_scenario(e.path().string());
    EXPECT_TRUE(s) << s.error();
    if (s) {
      EXPECT_FALSE(s->steps.empty()) << e.path();
    }
  }
  EXPECT_GE(files, 10u) << "the examples of docs/scenarios.md and their SOEM variants";
}

}  // namespace
}  // namespace ecat::scenario
