#include "apps/ecat-slave/device_list.hpp"

#include <fmt/format.h>

#include "esi/device_loader.hpp"
#include "esi/esi_reader.hpp"
#include "esi/twin_import.hpp"

namespace ecat::app {

Expected<std::vector<od::DeviceDescription>, std::string> load_devices(const SlaveProgramOptions& options) {
  std::vector<od::DeviceDescription> devices;
  for (const auto& file : options.device_files) {
    auto d = esi::load_device_file(file);
    if (!d) return fail(d.error().to_string());
    devices.push_back(std::move(*d));
  }
  for (const auto& file : options.esi_files) {
    std::vector<esi::EsiWarning> warnings;
    // The twin as ecat-esigen --from-esi --device-xml writes it and the loader
    // reads it back (docs/twins.md); --strict turns import warnings into errors.
    auto d = esi::import_twin(file, {{options.product_code, options.revision}, options.strict}, &warnings);
    for (const auto& w : warnings) {
      fmt::print(stderr, "ecat-slave: warning: {}\n", w.to_string(file));
    }
    if (!d) return fail(d.error().to_string());
    devices.push_back(std::move(*d));
  }
  if (devices.empty()) {
    auto d = esi::load_default_device();
    if (!d) return fail(d.error().to_string());
    devices.push_back(std::move(*d));
  }
  // --count N: the chain is the listed devices followed by copies of the last
  // one until it has N slaves.
  while (devices.size() < options.count) devices.push_back(devices.back());
  return devices;
}

}  // namespace ecat::app
