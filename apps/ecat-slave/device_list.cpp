#include "apps/ecat-slave/device_list.hpp"

#include <fmt/format.h>

#include "esi/device_loader.hpp"
#include "esi/eni_devices.hpp"
#include "esi/eni_reader.hpp"
#include "esi/esi_reader.hpp"
#include "esi/twin_import.hpp"

namespace ecat::app {

namespace {

// --eni [--esi-dir]: the ENI's chain; one line per slave says where its
// dictionary came from.
Expected<std::vector<od::DeviceDescription>, std::string> load_eni(const SlaveProgramOptions& options) {
  std::vector<esi::EsiWarning> warnings;
  auto net = esi::read_eni(options.eni_file, &warnings);
  if (!net) return fail(net.error().to_string());
  auto devs = esi::eni_devices(*net, options.esi_dir, &warnings);
  for (const auto& w : warnings) fmt::print(stderr, "ecat-slave: warning: {}\n", w.to_string(options.eni_file));
  if (!devs) return fail(devs.error().to_string());
  std::vector<od::DeviceDescription> devices;
  for (std::size_t i = 0; i < devs->size(); ++i) {
    auto& d = (*devs)[i];
    if (!options.quiet) {
      fmt::print(stderr, "ecat-slave: ENI slave {}: {} vendor #x{:08X} product #x{:08X} revision #x{:08X}: {}\n",
                 i + 1, net->slaves[i].name, d.device.identity.vendor_id, d.device.identity.product_code,
                 d.device.identity.revision,
                 d.esi_file.empty() ? std::string("dictionary synthesised from the ENI")
                                    : fmt::format("dictionary from {}", d.esi_file));
    }
    devices.push_back(std::move(d.device));
  }
  // The ENI's cyclic commands with their expected working counters (ETG.2100
  // Cyclic/Frame/Cmd/Cnt): what a master running this ENI checks each cycle.
  if (!options.quiet && !net->cyclic.empty()) {
    unsigned wkc = 0;
    for (const auto& c : net->cyclic) wkc += c.cnt;
    fmt::print(stderr, "ecat-slave: ENI cyclic: {} command(s), expected WKC {} per cycle\n", net->cyclic.size(), wkc);
  }
  return devices;
}

}  // namespace

Expected<std::vector<od::DeviceDescription>, std::string> load_devices(const SlaveProgramOptions& options) {
  if (!options.eni_file.empty()) return load_eni(options);
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
    auto d = esi::import_twin(
        file, {esi::EsiSelection{options.product_code, options.revision, options.type_name}, options.strict},
        &warnings);
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
