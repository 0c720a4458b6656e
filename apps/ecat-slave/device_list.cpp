#include "apps/ecat-slave/device_list.hpp"

#include <algorithm>

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
Expected<std::vector<od::DeviceDescription>, std::string> load_eni(SlaveProgramOptions& options) {
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
    options.eoe_init.push_back(eoe_init_expectations(net->slaves[i], options.eni_file));
    if (!options.eoe_init.back().empty() && !d.device.mailbox.eoe) {
      fmt::print(stderr,
                 "ecat-slave: warning: {}:{}: slave {} ({}): the ENI sends EoE InitCmds but the device lists no "
                 "EoE; it answers them with mailbox error 2 (unsupported protocol), as the device would\n",
                 options.eni_file, net->slaves[i].eoe_init_cmds.front().line, i + 1, net->slaves[i].name);
      options.eoe_init.back().clear();
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

std::vector<slave::EoeInitExpectation> eoe_init_expectations(const esi::EniSlave& s, const std::string& file) {
  std::vector<slave::EoeInitExpectation> out;
  for (const auto& c : s.eoe_init_cmds) {
    if (!c.set_ip) continue;
    for (const auto& t : c.transitions) {
      if (t != "IP" && t != "PS" && t != "SO") continue;  // the reader warned
      slave::EoeInitExpectation x;
      // ETG.1000.6 Set IP Parameter flags: the same bits on both sides.
      x.want.flags = c.ip.flags & (coe::eoe::kHasMac | coe::eoe::kHasIp | coe::eoe::kHasSubnet |
                                   coe::eoe::kHasGateway | coe::eoe::kHasDnsServer | coe::eoe::kHasDnsName);
      x.want.mac = c.ip.mac;
      x.want.ip = c.ip.ip;
      x.want.subnet = c.ip.subnet;
      x.want.gateway = c.ip.gateway;
      x.want.dns_server = c.ip.dns_server;
      std::copy_n(c.ip.dns_name.begin(), std::min(c.ip.dns_name.size(), x.want.dns_name.size()),
                  x.want.dns_name.begin());
      x.due = t == "SO" ? esc::AlState::Op : esc::AlState::SafeOp;
      x.where = fmt::format("{}:{} ({})", file, c.line, t);
      out.push_back(std::move(x));
    }
  }
  return out;
}

Expected<std::vector<od::DeviceDescription>, std::string> load_devices(SlaveProgramOptions& options) {
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
