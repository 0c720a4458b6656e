#include "esi/twin_import.hpp"

#include "esi/device_loader.hpp"
#include "esi/esi_writer_device_xml.hpp"

namespace ecat::esi {

std::optional<LoadError> strict_failure(const std::vector<EsiWarning>& warnings, const std::string& file) {
  if (warnings.empty()) return std::nullopt;
  const EsiWarning& w = warnings.front();
  return LoadError{file, w.line, w.element + ": " + w.message + " (--strict: import warnings are errors)"};
}

Expected<od::DeviceDescription, LoadError> import_twin(const std::filesystem::path& path,
                                                       const TwinImportOptions& options,
                                                       std::vector<EsiWarning>* warnings) {
  std::vector<EsiWarning> local;
  std::vector<EsiWarning>& w = warnings ? *warnings : local;
  auto imported = read_esi(path, options.selection, &w);
  if (!imported) return fail(imported.error());
  if (options.strict) {
    if (auto f = strict_failure(w, path.string())) return fail(*f);
  }
  // The twin is the device file of the import, as the loader reads it back.
  auto twin = load_device_string(write_device_xml(*imported), path.string() + " (as device XML)");
  if (!twin) return fail(twin.error());
  twin->source_file = path.string();
  return twin;
}

}  // namespace ecat::esi
