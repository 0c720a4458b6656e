// The conformance cases each failing-slave test file proves (issue 31 item
// 3): conformance_proofs_test.cpp checks that together they name every case
// of the suite (conformance::all_cases(), the list `ecat-conform --list`
// prints, and the device-file cases esi.* it adds with --device/--esi), so a
// new case cannot be added without a breakage.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

namespace ecat::master::test {

std::vector<std::string> proven_core_cases();     // conformance_broken_core_test.cpp
std::vector<std::string> proven_esc_cases();      // conformance_esc_cases_test.cpp
std::vector<std::string> proven_drive_cases();    // conformance_broken_drive_test.cpp (CiA 402)
std::vector<std::string> proven_history_cases();  // conformance_broken_drive_test.cpp (10F3h)
std::vector<std::string> proven_foe_cases();      // conformance_broken_foe_test.cpp
std::vector<std::string> proven_eoe_cases();      // conformance_broken_eoe_test.cpp
std::vector<std::string> proven_error_field_cases();  // conformance_broken_drive_test.cpp (1003h)
std::vector<std::string> proven_esi_cases();      // conformance_broken_esi_test.cpp (ecat-conform's esi.*)

// The case names a file's breakage table proves (its proven_*_cases()).
template <typename Breakages>
std::vector<std::string> case_names(const Breakages& breakages) {
  std::vector<std::string> names;
  for (const auto& b : breakages) names.emplace_back(b.case_name);
  return names;
}

// Every case of a group has a breakage in the table (each file's coverage test).
template <typename Cases, typename Breakages>
void expect_every_case_broken(const Cases& cases, const Breakages& breakages) {
  const std::vector<std::string> names = case_names(breakages);
  for (const auto& c : cases) {
    EXPECT_TRUE(std::find(names.begin(), names.end(), c.name) != names.end()) << c.name;
  }
}

}  // namespace ecat::master::test
