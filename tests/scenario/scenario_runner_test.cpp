// The scenario runner (scenario/scenario_runner.hpp) on simulated time: an
// in-process master and a generic servo, the runner polled once per master
// cycle. Each test checks what each step saw, when, and the verdict.
#include <gtest/gtest.h>

#include "control/event_queue.hpp"
#include "control/request_handler.hpp"
#include "scenario/junit_report.hpp"
#include "scenario/scenario_runner.hpp"
#include "slave/fault_catalogue.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::scenario {
namespace {

using std::chrono::milliseconds;

constexpr Nanoseconds kCycle = milliseconds(1);
// One master cycle of simulated time: the period and its one frame's wire time.
constexpr Nanoseconds kStep = kCycle + test::kWireTime;

struct Rig {
  test::InProcess p;
  std::unique_ptr<slave::FaultCatalogue> faults;
  control::EventQueue events;
  std::unique_ptr<control::RequestHandler> handler;
  std::uint64_t cycles = 0;

  Rig() {
    p.add_default(1);
    EXPECT_EQ(p.bring_up(), "");
    faults = std::make_unique<slave::FaultCatalogue>(p.chain);
    handler = std::make_unique<control::RequestHandler>(p.chain, p.clock, events, faults.get());
  }
  // Master cycles with the runner polled after each, until it is done or `max` cycles ran.
  void run(ScenarioRunner& r, std::uint64_t max) {
    for (std::uint64_t i = 0; i < max && !r.done(); ++i) {
      (void)p.cycle_once(kCycle);
      ++cycles;
      r.poll(p.clock.now(), cycles);
    }
  }
  ScenarioRunner runner(const char* text) {
    auto s = parse_scenario(text, "t.yaml");
    EXPECT_TRUE(s) << s.error();
    return ScenarioRunner(std::move(*s), *handler, true);
  }
};

TEST(ScenarioRunner, DriveFaultSeenByTheMasterThenCleared) {
  Rig rig;
  auto r = rig.runner(R"(name: drive fault
steps:
  - name: over-current
    after: 5ms
    do: {cmd: fault_engage, kind: drive_fault, slave: 0, params: {code: 0x2310}}
    save: oc
  - name: EMCY 2310h
    expect: {type: emergency, slave: 0, error_code: 0x2310}
    within: 50ms
  - name: statusword Fault
    expect: {read: {slave: 0, index: 0x6041}, mask: 0x4F, equals: 0x08}
    within: 20ms
  - name: 603Fh
    expect: {read: {slave: 0, index: 0x603F}, equals: 0x2310}
    within: 1ms
  - name: cleared
    after_frames: 3
    do: {cmd: fault_clear, fault: "${oc.fault}"}
  - name: the fault_cleared event
    expect: {type: fault_cleared, kind: drive_fault, slave: 0}
    within: 20ms
)");
  rig.run(r, 1000);
  ASSERT_TRUE(r.done());
  EXPECT_TRUE(r.passed()) << r.summary();
  const auto& res = r.results();
  ASSERT_EQ(res.size(), 6u);
  // The fault is engaged 5 ms after the start (the first poll, cycle 1).
  EXPECT_EQ(res[0].ended, 5 * kStep);
  EXPECT_EQ(res[0].message, R"(fault_engage: {"fault":1})");
  // The drive latches it at its next cycle and raises the EMCY; the event
  // is found at the next 10 ms sample.
  EXPECT_EQ(res[1].message.substr(0, 10), "seen after");
  EXPECT_NE(res[1].message.find(R"("error_code":8976)"), std::string::npos) << res[1].message;
  EXPECT_LE(res[1].ended, milliseconds(16));
  EXPECT_EQ(res[2].message, "seen after 0 ms: 0x218 (536)");  // 0x0218: Fault, voltage enabled, remote
  EXPECT_EQ(res[3].message, "seen after 0 ms: 0x2310 (8976)");
  EXPECT_EQ(res[4].ended - res[3].ended, 3 * kStep);
  // The fault_cleared event is pushed by the request itself: the next step sees it at once.
  EXPECT_EQ(res[5].ended, res[4].ended);
  EXPECT_NE(res[5].message.find(R"("type":"fault_cleared")"), std::string::npos) << res[5].message;
  EXPECT_EQ(res[4].message, R"(fault_clear: {"cleared":1})");
  EXPECT_TRUE(rig.faults->engaged().empty());
}

TEST(ScenarioRunner, AnExpectationNotMetFailsAndSkipsTheRest) {
  Rig rig;
  auto r = rig.runner(R"(name: never
steps:
  - name: Switched on
    expect: {read: {slave: 0, index: 0x6041}, mask: 0x6F, equals: 0x23}
    within: 30ms
  - do: {cmd: hello}
)");
  rig.run(r, 1000);
  ASSERT_TRUE(r.done());
  EXPECT_FALSE(r.passed());
  EXPECT_EQ(r.results()[0].status, StepResult::Status::Failed);
  EXPECT_EQ(r.results()[0].ended, 30 * kStep);
  EXPECT_EQ(r.results()[0].message, "not seen within 30 ms; last value 0x250 (592)");
  EXPECT_EQ(r.results()[1].status, StepResult::Status::Skipped);
  EXPECT_EQ(rig.cycles, 31u);
  EXPECT_EQ(r.summary(),
            "  FAIL Switched on (t.yaml:3) at 30.150 ms: not seen within 30 ms; last value 0x250 (592)\n"
            "  SKIP step 2 (t.yaml:6) at 30.150 ms: an earlier step failed\n"
            "scenario never: FAILED (2 steps, 1 failed, 30.150 ms)\n");
  const std::string xml = junit_xml(r);
  EXPECT_NE(xml.find(R"(<testsuite name="never" tests="2" failures="1" errors="0" skipped="1" time="0.030" file="t.yaml">)"),
            std::string::npos)
      << xml;
  EXPECT_NE(xml.find(R"x(<failure message="not seen within 30 ms; last value 0x250 (592)" />)x"), std::string::npos)
      << xml;
  EXPECT_NE(xml.find(R"(<skipped message="an earlier step failed" />)"), std::string::npos) << xml;
}

// A register read (docs/scenarios.md): the master brought the servo to Op,
// so AL status 0x0130 reads 0x0008; a mask goes with min/max as well (the
// station address the master gave, 0x1001: 0x1000 through a mask with min/max).
TEST(ScenarioRunner, RegistersReadWithMaskEqualsAndBounds) {
  Rig rig;
  auto r = rig.runner(R"(name: registers
steps:
  - expect: {read: {slave: 0, register: 0x0130}, mask: 0x000F, equals: 0x0008}
    within: 1ms
  - expect: {read: {slave: 0, register: 0x0010, size: 2}, mask: 0xF000, min: 0x1000, max: 0x1000}
    within: 1ms
  - expect: {read: {slave: 0, register: 0x0130}, mask: 0x000F, min: 0x09}
    within: 3ms
)");
  rig.run(r, 100);
  ASSERT_TRUE(r.done());
  const auto& res = r.results();
  ASSERT_EQ(res.size(), 3u);
  EXPECT_EQ(res[0].message, "seen after 0 ms: 0x8 (8)");
  EXPECT_EQ(res[1].message, "seen after 0 ms: 0x1001 (4097)");  // the message shows the value before the mask
  EXPECT_EQ(res[2].status, StepResult::Status::Failed);
  EXPECT_EQ(res[2].message, "not seen within 3 ms; last value 0x8 (8)");
}

TEST(ScenarioRunner, WhenAnEventThenExpectNot) {
  Rig rig;
  auto r = rig.runner(R"(name: safeop
steps:
  - name: master leaves Op
    when: {type: al_state, slave: 0, from: Op, to: SafeOp}
  - name: no error with it
    expect_not: {type: al_state, slave: 0, error: true}
    for: 50ms
  - name: the master asks for Op again
    expect: {type: al_control, slave: 0, requested: OP}
    within: 100ms
)");
  rig.run(r, 20);
  EXPECT_FALSE(r.done());
  EXPECT_EQ(r.results()[0].status, StepResult::Status::Pending);
  ASSERT_TRUE(rig.p.master.request_state(0, master::AlState::SafeOp));
  rig.run(r, 60);
  EXPECT_EQ(r.results()[0].status, StepResult::Status::Passed);
  EXPECT_EQ(r.results()[1].status, StepResult::Status::Passed);
  EXPECT_EQ(r.results()[1].message, "not seen for 50 ms");
  ASSERT_TRUE(rig.p.master.request_state(0, master::AlState::Op));
  rig.run(r, 100);
  ASSERT_TRUE(r.done());
  EXPECT_TRUE(r.passed()) << r.summary();
}

TEST(ScenarioRunner, ExpectNotSeenFails) {
  Rig rig;
  auto r = rig.runner(R"(name: stays in Op
steps:
  - expect_not: {type: al_state, slave: 0}
    for: 1s
)");
  rig.run(r, 20);
  ASSERT_TRUE(rig.p.master.request_state(0, master::AlState::SafeOp));
  rig.run(r, 100);
  ASSERT_TRUE(r.done());
  EXPECT_FALSE(r.passed());
  EXPECT_NE(r.results()[0].message.find(R"(seen, which must not happen, after)"), std::string::npos);
  EXPECT_NE(r.results()[0].message.find(R"("from":"OP")"), std::string::npos) << r.results()[0].message;
}

TEST(ScenarioRunner, BadRequestsAndReferencesFailTheStep) {
  Rig rig;
  auto r = rig.runner(R"(steps:
  - do: {cmd: fault_clear, fault: "${nothing.fault}"}
)");
  rig.run(r, 5);
  EXPECT_EQ(r.results()[0].status, StepResult::Status::Failed);
  EXPECT_EQ(r.results()[0].message, "${nothing.fault}: no earlier step saved 'nothing'");
  auto r2 = rig.runner(R"(steps:
  - do: {cmd: fault_engage, kind: drive_fault, slave: 4, params: {code: 1}}
)");
  rig.run(r2, 5);
  EXPECT_EQ(r2.results()[0].status, StepResult::Status::Failed);
  EXPECT_EQ(r2.results()[0].message.substr(0, 37), "fault_engage refused: unknown_slave: ");
  auto r3 = rig.runner(R"(steps:
  - expect: {read: {slave: 0, index: 0x5FFF}, equals: 1}
)");
  rig.run(r3, 5);
  EXPECT_EQ(r3.results()[0].status, StepResult::Status::Failed);
  EXPECT_EQ(r3.results()[0].message.substr(0, 30), "read refused: unknown_object: ")
      << r3.results()[0].message;
}

TEST(ScenarioRunner, TimeoutEndsAWaitingScenario) {
  Rig rig;
  auto r = rig.runner(R"(name: t
timeout: 40ms
steps:
  - when: {type: link, slave: 0}
  - do: {cmd: hello}
)");
  rig.run(r, 1000);
  ASSERT_TRUE(r.done());
  EXPECT_EQ(r.results()[0].message, "the scenario's timeout (40 ms) ran out before this step's trigger");
  EXPECT_EQ(rig.cycles, 41u);  // the first poll (cycle 1) starts it; 40 cycles later 40.2 ms have passed
}

}  // namespace
}  // namespace ecat::scenario
