#include "slave/esc_setup.hpp"

#include "esi/sii_writer.hpp"
#include "od/process_directions.hpp"
#include "slave/shared_eeprom.hpp"

namespace ecat::slave {
namespace {

const od::SyncManagerConfig* find_sm(const od::DeviceDescription& device, od::SmType type) {
  for (const auto& sm : device.sync_managers) {
    if (sm.type == type) return &sm;
  }
  return nullptr;
}

}  // namespace

Expected<esc::EscConfig, std::string> esc_config_for(const od::DeviceDescription& device,
                                                     std::span<const esc::InnerDelayFigures> delay_figures) {
  auto sii = esi::write_sii(device);
  if (!sii) return fail(sii.error());

  const od::EscProperties& p = device.esc;
  esc::EscConfig c;
  c.type = p.esc_type;
  c.revision = p.revision;
  c.build = p.build;
  c.fmmu_count = p.fmmu_count;
  c.sync_manager_count = p.sm_count;
  c.process_ram_size = p.process_ram_bytes;
  c.dc = p.dc_supported;
  c.dc_64bit = p.dc_supported && p.dc_64bit;
  c.lrw = !p.no_lrw;
  c.read_write_commands = !p.no_read_write;
  // Port descriptor 0x0007 from the ESI Physics letters (Section II 0x0007:
  // 11 MII, 10 E-bus, 00 not implemented).
  std::uint8_t ports = 0;
  for (std::size_t n = 0; n < p.physics.size() && n < esc::kMaxPorts; ++n) {
    esc::PortType t = esc::PortType::NotImplemented;
    if (p.physics[n] == 'Y' || p.physics[n] == 'H') t = esc::PortType::Mii;
    if (p.physics[n] == 'K') t = esc::PortType::Ebus;
    ports = static_cast<std::uint8_t>(ports | esc::port_descriptor_bits(static_cast<unsigned>(n), t));
  }
  c.port_descriptor = ports;
  // Time inside the ESC from its type's figures, per port type (docs/esc.md
  // "Forwarding delay figures per ESC type").
  // A type the table does not name keeps the EscConfig defaults (0).
  if (const esc::InnerDelayFigures* figures = esc::find_inner_delays(delay_figures, c.type)) {
    const esc::InnerDelays inner = esc::inner_delays_for(figures, esc::port_types(ports));
    c.processing_delay = inner.processing;
    for (unsigned n = 1; n < esc::kMaxPorts; ++n) c.port_forwarding_delay[n] = inner.forwarding[n];
  }
  c.sii = shared_eeprom_image(std::move(*sii));
  return c;
}

esc::EsmConfig esm_config_for(const od::DeviceDescription& device) {
  esc::EsmConfig c;
  const auto* out = find_sm(device, od::SmType::MailboxOut);
  const auto* in = find_sm(device, od::SmType::MailboxIn);
  c.has_mailbox = out != nullptr && in != nullptr;
  if (out) c.mailbox_out = {out->start_address, out->default_size, out->control};
  if (in) c.mailbox_in = {in->start_address, in->default_size, in->control};
  c.bootstrap_supported = device.bootstrap_supported;
  // Every process-data SM of a direction the device has PDOs for (several
  // per direction where the device has them, e.g. EK1828's SM0/SM1).
  for (std::size_t n = 0; n < device.sync_managers.size(); ++n) {
    const od::SyncManagerConfig& sm = device.sync_managers[n];
    const bool outputs = sm.type == od::SmType::Outputs;
    if (!outputs && sm.type != od::SmType::Inputs) continue;
    if (!od::has_process_data(device, outputs)) continue;
    c.add_process_sm({static_cast<std::uint8_t>(n), outputs, sm.start_address, sm.control});
  }
  c.device_id = device.esc.configured_station_alias;
  return c;
}

}  // namespace ecat::slave
