// ESI import (ETG.2000): reads one device of a vendor's EtherCATInfo file into
// the device model, so the emulator can pose as any device that has an ESI.
// What the model cannot express is skipped with a warning naming the element
// and its line; what makes the file unusable is a LoadError "file:line: ...".
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/expected.hpp"
#include "esi/device_error.hpp"
#include "od/device.hpp"

namespace ecat::esi {

struct EsiWarning {
  std::string element;  // element name ("Slots", "InitCmd", ...)
  SourcePos line;       // the element's line (and column, common/source_pos.hpp)
  std::string message;
  // "file:line: warning: <element>: message"
  std::string to_string(std::string_view file) const;
};

// Which device of a file with several: by product code, revision and/or type
// name (Type element text), all given ones must match and exactly one device
// may match (else an error listing the candidates, esi_device_list.hpp).
// None given: the first device in the file (a warning names the others).
struct EsiSelection {
  std::optional<std::uint32_t> product_code;
  std::optional<std::uint32_t> revision;
  std::optional<std::string> type_name;
};

Expected<od::DeviceDescription, LoadError> read_esi(const std::filesystem::path& path,
                                                    std::optional<std::uint32_t> product_code = {},
                                                    std::optional<std::uint32_t> revision = {},
                                                    std::vector<EsiWarning>* warnings = nullptr);

Expected<od::DeviceDescription, LoadError> read_esi(const std::filesystem::path& path,
                                                    const EsiSelection& selection,
                                                    std::vector<EsiWarning>* warnings = nullptr);

// `name` is used in messages.
Expected<od::DeviceDescription, LoadError> read_esi_string(std::string_view xml,
                                                           std::string_view name,
                                                           const EsiSelection& selection = {},
                                                           std::vector<EsiWarning>* warnings = nullptr);

// ESI HexDecValue ("#x1A00", "6656") or C hex ("0x1A00") as a 32-bit number,
// for command lines; nullopt if it is none of these or too large.
std::optional<std::uint32_t> parse_esi_number(std::string_view text);

}  // namespace ecat::esi
