#include "scenario/junit_report.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <pugixml.hpp>

namespace ecat::scenario {
namespace {

std::string seconds(Nanoseconds d) { return fmt::format("{:.3f}", static_cast<double>(d.count()) / 1e9); }

}  // namespace

std::string junit_xml(const ScenarioRunner& run) {
  const Scenario& sc = run.scenario();
  const auto& results = run.results();
  const auto count = [&](StepResult::Status s) {
    return std::count_if(results.begin(), results.end(), [&](const StepResult& r) { return r.status == s; });
  };
  pugi::xml_document doc;
  pugi::xml_node suites = doc.append_child("testsuites");
  pugi::xml_node suite = suites.append_child("testsuite");
  suite.append_attribute("name") = sc.name.c_str();
  suite.append_attribute("tests") = static_cast<unsigned long long>(results.size());
  suite.append_attribute("failures") = static_cast<long long>(count(StepResult::Status::Failed));
  suite.append_attribute("errors") = static_cast<long long>(count(StepResult::Status::Pending));
  suite.append_attribute("skipped") = static_cast<long long>(count(StepResult::Status::Skipped));
  suite.append_attribute("time") = seconds(run.elapsed()).c_str();
  suite.append_attribute("file") = sc.file.c_str();
  for (std::size_t i = 0; i < results.size(); ++i) {
    const Step& step = sc.steps[i];
    const StepResult& r = results[i];
    pugi::xml_node tc = suite.append_child("testcase");
    tc.append_attribute("name") = step.name.c_str();
    tc.append_attribute("classname") = sc.name.c_str();
    tc.append_attribute("file") = sc.file.c_str();
    tc.append_attribute("line") = step.line;
    tc.append_attribute("time") = seconds(r.ended - r.started).c_str();
    switch (r.status) {
      case StepResult::Status::Passed:
        tc.append_child("system-out").text() = r.message.c_str();
        break;
      case StepResult::Status::Failed:
        tc.append_child("failure").append_attribute("message") = r.message.c_str();
        break;
      case StepResult::Status::Skipped:
        tc.append_child("skipped").append_attribute("message") = r.message.c_str();
        break;
      case StepResult::Status::Pending:
        tc.append_child("error").append_attribute("message") = "the scenario ended before this step ran";
        break;
    }
  }
  std::ostringstream out;
  doc.save(out, "  ");
  return out.str();
}

Expected<void, std::string> write_junit(const ScenarioRunner& run, const std::string& path) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << junit_xml(run);
  out.close();
  if (!out) return fail(fmt::format("{}: cannot write the JUnit report", path));
  return {};
}

}  // namespace ecat::scenario
