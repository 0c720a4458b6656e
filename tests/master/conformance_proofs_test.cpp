// Every case of the conformance suite has a failing-slave proof (issue 31
// item 3): the cases the proof files name (conformance_proofs.hpp) are
// exactly conformance::all_cases() and ecat-conform's device-file cases - the
// list `ecat-conform --device FILE --list` prints (tests/scripts/
// conform_proofs.sh compares with the program's own output).
// A new case without a breakage, or a breakage for a case that no longer
// exists, fails here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <set>

#include "apps/ecat-conform/target.hpp"
#include "conformance_proofs.hpp"
#include "esi/device_loader.hpp"
#include "master/conformance/suite.hpp"

namespace ecat::master::test {
namespace {

std::multiset<std::string> proven() {
  std::multiset<std::string> all;
  for (const auto& list : {proven_core_cases(), proven_esc_cases(), proven_drive_cases(), proven_history_cases(),
                           proven_foe_cases(), proven_eoe_cases(), proven_error_field_cases(), proven_esi_cases()}) {
    all.insert(list.begin(), list.end());
  }
  return all;
}

TEST(ConformanceProofs, EveryCaseOfTheSuiteIsProvenOnce) {
  const auto done = proven();
  std::set<std::string> listed;
  auto cases = conformance::all_cases();
  auto device = esi::load_default_device();  // the esi.* cases' names do not depend on the device
  ASSERT_TRUE(device);
  for (auto& c : conform::device_file_cases(*device)) cases.push_back(std::move(c));
  for (const auto& c : cases) {
    listed.insert(c.name);
    EXPECT_EQ(done.count(c.name), 1u) << c.name << ": no failing-slave test (or more than one list names it)";
  }
  for (const auto& name : done) EXPECT_EQ(listed.count(name), 1u) << name << ": proven but not in the suite";
  // ECAT_PRINT_PROVEN=1 prints the proven names, one a line (conform_proofs.sh).
  if (std::getenv("ECAT_PRINT_PROVEN") != nullptr) {
    for (const auto& name : std::set<std::string>(done.begin(), done.end())) std::printf("proven %s\n", name.c_str());
  }
}

}  // namespace
}  // namespace ecat::master::test
