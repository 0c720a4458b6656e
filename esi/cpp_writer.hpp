// C++ tables of a device description for embedded use (STYLE lesson 3: one
// source, many outputs): a self-contained header with constexpr identity, sync
// managers, object dictionary (sorted by index, with default/min/max bytes in
// one pool) and PDOs. Compiles standalone with -std=c++20 -Wall -Wextra
// -Wpedantic; deterministic output.
#pragma once

#include <string>
#include <string_view>

#include "od/device.hpp"

namespace ecat::esi {

// `ns` is the namespace the tables go in (a C++ identifier, may contain ::).
std::string write_cpp_tables(const od::DeviceDescription& device,
                             std::string_view ns = "ecat_device");

}  // namespace ecat::esi
