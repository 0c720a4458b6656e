// The devices of a multi-device ESI (ETG.2000 Descriptions/Devices/Device):
// listing them (`ecat-esigen --from-esi FILE --list`) and choosing one by
// product code, revision and/or type name (`--product-code`, `--revision`,
// `--type` of ecat-esigen and ecat-slave). A selection that matches no device,
// or more than one, is an error that lists the candidates (docs/twins.md
// "Choosing a device of a multi-device ESI").
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/expected.hpp"
#include "esi/device_error.hpp"
#include "esi/esi_reader.hpp"

namespace ecat::esi {

// One Device element as the listing shows it.
struct EsiDeviceEntry {
  std::string type;               // Type element text (order code)
  std::string name;               // Name (LcId 1033, else the first)
  std::string product_code_text;  // Type@ProductCode as written
  std::string revision_text;      // Type@RevisionNo as written
  std::optional<std::uint32_t> product_code;  // nullopt: absent or not a number
  std::optional<std::uint32_t> revision;
  SourcePos line;  // of the Device element
};

// The stable one-line form of --list: four tab-separated fields
//   TYPE <TAB> #xPPPPPPPP <TAB> #xRRRRRRRR <TAB> NAME
// product code and revision as 8-digit ESI hex ("?" if absent, the text as
// written if it is not a number).
std::string format_device_line(const EsiDeviceEntry& entry);

// "TYPE (product code #x.., revision #x.., line N)" for messages.
std::string describe_device(const EsiDeviceEntry& entry);

// " type 'X' product code #x.. revision #x.." for messages ("" if empty).
std::string describe_selection(const EsiSelection& selection);

bool selection_given(const EsiSelection& selection) noexcept;
bool selection_matches(const EsiSelection& selection, const EsiDeviceEntry& entry);

// Every Device of the file, in file order; an error if the file is no ESI or
// describes no device. `name` is used in messages.
Expected<std::vector<EsiDeviceEntry>, LoadError> list_esi_devices(std::string_view xml,
                                                                  std::string_view name);
Expected<std::vector<EsiDeviceEntry>, LoadError> list_esi_file(const std::filesystem::path& path);

}  // namespace ecat::esi
