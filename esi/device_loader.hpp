// Loader of the ecatslave device description format (docs/device-format.md,
// xml/schema/device.xsd): reads a device file with its includes, checks it
// and returns the one model everything else works from.
//
//   auto dev = ecat::esi::load_device_file("xml/devices/generic-servo.xml");
//   if (!dev) std::cerr << dev.error().to_string() << '\n';  // "file:line: message"
#pragma once

#include <filesystem>
#include <string_view>

#include "common/expected.hpp"
#include "esi/device_error.hpp"
#include "od/device.hpp"

namespace ecat::esi {

// Includes resolve relative to the file; "../profiles/NAME.xml" falls back to
// the profile built into the program when it is not on disk.
Expected<od::DeviceDescription, LoadError> load_device_file(const std::filesystem::path& path);

// `name` is used in messages and as the base for relative includes.
Expected<od::DeviceDescription, LoadError> load_device_string(std::string_view xml,
                                                              std::string_view name);

// The built-in generic CiA 402 servo (xml/devices/generic-servo.xml).
Expected<od::DeviceDescription, LoadError> load_default_device();

}  // namespace ecat::esi
