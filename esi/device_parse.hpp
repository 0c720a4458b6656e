// Reads one device or profile file into the DeviceSpec being built, applying
// the override/extend rules of docs/device-format.md. Includes are handed to
// the caller, which finds and reads them (esi/device_loader.cpp).
#pragma once

#include <functional>
#include <string_view>

#include "esi/device_spec.hpp"
#include "esi/xml_schema.hpp"

namespace ecat::esi {

inline constexpr int kFormatVersion = 1;

using IncludeHandler = std::function<void(const Where& where, std::string_view href)>;

// Parses `text` (named `file` in messages), checks it against the schema and
// merges it into `spec`. Throws LoadFailure (esi/device_failure.hpp).
void parse_device_text(std::string_view text, const std::string& file, const SchemaValidator& schema,
                       DeviceSpec& spec, const IncludeHandler& on_include);

// "6040h" / "6040h:01", the form every message uses.
std::string object_name(std::uint16_t index);
std::string entry_name(std::uint16_t index, std::uint8_t sub);

}  // namespace ecat::esi
