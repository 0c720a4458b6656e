// Typed reads of element attributes for the device builder. Each read that
// fails throws LoadFailure at the attribute's file:line.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "esi/device_spec.hpp"

namespace ecat::esi {

// The location of `name` if given, else of the element.
Where where_of(const ElementSpec& e, std::string_view name);

std::string attr_text(const ElementSpec& e, std::string_view name, std::string_view fallback = {});
bool attr_bool(const ElementSpec& e, std::string_view name, bool fallback);
std::uint64_t attr_unsigned(const ElementSpec& e, std::string_view name, std::uint64_t max,
                            std::uint64_t fallback);
std::int64_t attr_signed(const ElementSpec& e, std::string_view name, std::int64_t min,
                         std::int64_t max, std::int64_t fallback);

// Blank-separated list items of attribute `name` (empty if absent).
std::vector<std::string> attr_list(const ElementSpec& e, std::string_view name);

}  // namespace ecat::esi
