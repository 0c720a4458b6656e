// A vendor ESI device as a digital twin (docs/twins.md): the ESI import with
// the twin repairs, then through our device XML and its loader, so the twin
// a program runs is exactly the device file `ecat-esigen --from-esi
// --device-xml` writes and the loader accepts (with the objects the loader
// derives: 1018h, 1C00h, 1C12h/1C13h, 16xxh/1Axxh; and its checks).
#pragma once

#include <filesystem>
#include <vector>

#include "common/expected.hpp"
#include "esi/device_error.hpp"
#include "esi/esi_reader.hpp"
#include "od/device.hpp"

namespace ecat::esi {

struct TwinImportOptions {
  EsiSelection selection;
  // Every import warning (a repair or something not modelled) is an error.
  bool strict = false;
};

Expected<od::DeviceDescription, LoadError> import_twin(const std::filesystem::path& path,
                                                       const TwinImportOptions& options,
                                                       std::vector<EsiWarning>* warnings = nullptr);

// With strict: the first warning as a LoadError ("file:line: <element>: message
// (--strict)"); otherwise nothing.
std::optional<LoadError> strict_failure(const std::vector<EsiWarning>& warnings, const std::string& file);

}  // namespace ecat::esi
