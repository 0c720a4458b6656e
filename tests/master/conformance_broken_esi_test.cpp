// The four device-file cases of ecat-conform (`esi.*`, apps/ecat-conform/
// device_cases.cpp: the device file, i.e. the ESI source, against what the
// slave reports over the bus). The slave is always the shipped generic servo;
// the cases pass when they are given that same file, and each fails when it
// is given a copy of the file broken in exactly what it compares (issue 31
// item 3) - as it would when `ecat-conform --esi FILE` names a device file
// that does not describe the slave on the bus.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "apps/ecat-conform/target.hpp"
#include "conformance_proofs.hpp"
#include "esi/device_loader.hpp"
#include "in_process_bus.hpp"
#include "master/conformance/suite.hpp"

namespace ecat::master::test {
namespace {

using conformance::Verdict;

// One text replacement in xml/devices/generic-servo.xml.
struct EsiBreakage {
  const char* case_name;
  const char* from;
  const char* to;
};

std::vector<EsiBreakage> esi_breakages() {
  return {
      // SM0 (mailbox out) 96 bytes in the file, 128 in the SII.
      {"esi.sync_managers_match_sii", R"(type="MailboxOut" start="#x1000" size="128")",
       R"(type="MailboxOut" start="#x1000" size="96")"},
      // The file announces FoE; the slave's SII word 0x1C does not.
      {"esi.mailbox_matches_sii", R"(coe="true" foe="false")", R"(coe="true" foe="true")"},
      // 4 FMMUs in the file, 8 in register 0x0004.
      {"esi.esc_matches_registers", R"(fmmus="8")", R"(fmmus="4")"},
      // 1601h without its last entry (60B1h) in the file, three entries in the dictionary.
      {"esi.pdo_mappings_match_od", R"(<Entry index="#x60B1" sub="0" bits="32"/>)", ""},
  };
}

std::string servo_text() {
  std::ifstream in(device_path("generic-servo.xml"));
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The `esi.*` case `name` run against a generic servo, comparing with `description`.
conformance::Report run_case(const od::DeviceDescription& description, const std::string& name) {
  InProcessBus bus;
  EXPECT_TRUE(bus.add(device_path("generic-servo.xml")));
  Master master(bus.transport, bus.clock);
  conformance::SuiteOptions options;
  options.wait = [&bus](Nanoseconds d) { bus.wait(d); };
  options.filter = name;
  const auto reports = conformance::run_suite(master, options, conform::device_file_cases(description));
  EXPECT_EQ(reports.size(), 1u) << name;
  return reports.empty() ? conformance::Report{} : reports[0];
}

TEST(ConformanceEsi, EveryCasePassesOnTheShippedFile) {
  auto shipped = esi::load_device_file(device_path("generic-servo.xml"));
  ASSERT_TRUE(shipped) << shipped.error().to_string();
  for (const auto& c : conform::device_file_cases(*shipped)) {
    const auto r = run_case(*shipped, c.name);
    EXPECT_EQ(r.result.verdict, Verdict::Pass) << c.name << ": expected " << r.result.expected << ", seen "
                                               << r.result.seen;
  }
}

TEST(ConformanceEsi, EachCaseFailsOnABrokenCopyOfTheFile) {
  const std::string text = servo_text();
  ASSERT_FALSE(text.empty());
  for (const auto& b : esi_breakages()) {
    std::string broken = text;
    const auto at = broken.find(b.from);
    ASSERT_NE(at, std::string::npos) << b.case_name << ": " << b.from;
    ASSERT_EQ(broken.find(b.from, at + 1), std::string::npos) << b.case_name << ": not unique";
    broken.replace(at, std::string(b.from).size(), b.to);
    auto description = esi::load_device_string(broken, device_path("generic-servo.xml"));
    ASSERT_TRUE(description) << b.case_name << ": " << description.error().to_string();
    const auto r = run_case(*description, b.case_name);
    EXPECT_EQ(r.result.verdict, Verdict::Fail) << b.case_name << ": expected " << r.result.expected << ", seen "
                                               << r.result.seen;
    EXPECT_NE(r.result.expected, r.result.seen) << b.case_name;
  }
}

TEST(ConformanceEsi, EveryCaseHasABreakage) {
  auto shipped = esi::load_default_device();
  ASSERT_TRUE(shipped);
  expect_every_case_broken(conform::device_file_cases(*shipped), esi_breakages());
}

}  // namespace

std::vector<std::string> proven_esi_cases() {
  return case_names(esi_breakages());
}

}  // namespace ecat::master::test
