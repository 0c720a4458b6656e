// Files compiled into the esi library (cmake/EmbedFiles.cmake): the device
// schema, the CiA profiles and the default device, named by their path
// below xml/ ("schema/device.xsd", "profiles/cia402.xml",
// "devices/generic-servo.xml"). The xml/ folder stays the single source; the
// copies only let programs load devices from any working directory.
#pragma once

#include <optional>
#include <span>
#include <string_view>

namespace ecat::esi {

struct EmbeddedFile {
  std::string_view name;
  std::string_view content;
};

// Defined in the generated source in the build tree.
std::span<const EmbeddedFile> embedded_files() noexcept;

// The content of the embedded file `name`, if there is one.
std::optional<std::string_view> find_embedded(std::string_view name) noexcept;

// Names of the embedded files the loader uses.
inline constexpr std::string_view kEmbeddedSchema = "schema/device.xsd";
inline constexpr std::string_view kEmbeddedDefaultDevice = "devices/generic-servo.xml";

}  // namespace ecat::esi
