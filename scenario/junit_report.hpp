// A scenario's result as JUnit XML (the format CI systems read: Jenkins,
// GitLab, GitHub actions): one <testsuite> per scenario, one <testcase>
// per step with its time, <failure> with the reason, <skipped> for the
// steps after a failure.
#pragma once

#include <string>

#include "common/expected.hpp"
#include "scenario/scenario_runner.hpp"

namespace ecat::scenario {

std::string junit_xml(const ScenarioRunner& run);
Expected<void, std::string> write_junit(const ScenarioRunner& run, const std::string& path);

}  // namespace ecat::scenario
