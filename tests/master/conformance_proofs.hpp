// The conformance cases each failing-slave test file proves (issue 31 item
// 3): conformance_proofs_test.cpp checks that together they name every case
// of the suite (conformance::all_cases(), the list `ecat-conform --list`
// prints), so a new case cannot be added without a breakage.
#pragma once

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

}  // namespace ecat::master::test
