#include "esi/sii_writer.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "common/le.hpp"
#include "esi/sii_layout.hpp"
#include "esi/sii_strings.hpp"

namespace ecat::esi {
namespace {

// GENERAL physical ports (0x10): 4 bits per port from ESI Physics letters
// (sii-eeprom.md: Y or H -> 1 MII, K -> 3 EBUS, blank -> 0); "YY" = 0x0011,
// an EK1100-like "YKY" = 0x0131.
constexpr unsigned kPortNibbleBits = 4;
std::uint16_t physical_ports(const std::string& physics) {
  std::uint16_t v = 0;
  for (std::size_t p = 0; p < physics.size() && p < 4; ++p) {
    std::uint16_t nibble = sii::kPortNotUsed;
    if (physics[p] == 'Y' || physics[p] == 'H') nibble = sii::kPortMii;
    if (physics[p] == 'K') nibble = sii::kPortEbus;
    v = static_cast<std::uint16_t>(v | (nibble << (kPortNibbleBits * p)));
  }
  return v;
}

std::uint8_t fmmu_code(od::FmmuUsage u) {
  switch (u) {
    case od::FmmuUsage::Outputs: return sii::kFmmuOutputs;
    case od::FmmuUsage::Inputs: return sii::kFmmuInputs;
    case od::FmmuUsage::MailboxState: return sii::kFmmuSyncMStatus;
    case od::FmmuUsage::Unused: break;
  }
  return sii::kFmmuUnused;
}

// Process-data size of an SM whose device file leaves it to the PDOs: the
// default-assigned PDOs' bits, rounded up to bytes.
std::uint16_t pdo_bytes_for_sm(const od::DeviceDescription& d, std::size_t sm) {
  std::uint32_t bits = 0;
  for (const auto* list : {&d.rx_pdos, &d.tx_pdos}) {
    for (const auto& p : *list) {
      if (p.sm && *p.sm == sm) bits += p.bit_length();
    }
  }
  return static_cast<std::uint16_t>((bits + 7) / 8);
}

SiiPdo make_pdo(const od::Pdo& p, SiiStringTable& strings, bool entry_names) {
  SiiPdo out;
  out.index = p.index;
  out.sync_manager = p.sm ? *p.sm : sii::kPdoNoSm;
  out.name_idx = strings.add(p.name);
  out.flags = static_cast<std::uint16_t>((p.mandatory ? sii::kPdoMandatory : 0) |
                                         (p.sm ? sii::kPdoDefault : 0) |
                                         (p.fixed ? sii::kPdoFixed : 0));
  for (const auto& e : p.entries) {
    SiiPdoEntry se;
    se.index = e.index;
    se.subindex = e.subindex;
    se.name_idx = (e.index == 0 || !entry_names) ? 0 : strings.add(e.name);
    se.data_type = e.index == 0 ? 0 : static_cast<std::uint8_t>(static_cast<std::uint16_t>(e.type));
    se.bit_length = e.bit_length;
    out.entries.push_back(se);
  }
  return out;
}

}  // namespace

std::array<std::uint8_t, 14> sii_config_bytes(const od::EscProperties& esc) {
  std::array<std::uint8_t, 14> out{};
  ByteWriter w(out);
  w.u16(esc.pdi_control);
  w.u16(esc.pdi_configuration);
  w.u16(esc.sync_impulse_length);
  w.u16(esc.pdi_configuration2);
  w.u16(esc.configured_station_alias);
  return out;  // words 5 and 6 reserved, 0
}

const char* to_string(SiiDetail detail) noexcept {
  switch (detail) {
    case SiiDetail::Full: return "full";
    case SiiDetail::NoEntryNames: return "without PDO entry names";
    case SiiDetail::NoPdoDc: return "without PDO and DC categories";
  }
  return "?";
}

SiiImage sii_from_device(const od::DeviceDescription& d, SiiDetail detail) {
  SiiImage img;
  const auto cfg = sii_config_bytes(d.esc);
  ByteReader r(cfg);
  img.config = {r.u16(), r.u16(), r.u16(), r.u16(), r.u16(), r.u16(), r.u16()};
  img.vendor_id = d.identity.vendor_id;
  img.product_code = d.identity.product_code;
  img.revision = d.identity.revision;
  img.serial = d.identity.serial;

  // Mailbox words 18h..1Bh mirror SM0/SM1 (checked by the ESC at Init->PreOp);
  // Bootstrap reuses the standard mailbox when the device supports it.
  for (const auto& sm : d.sync_managers) {
    if (sm.type == od::SmType::MailboxOut) {
      img.standard_mailbox.receive_offset = sm.start_address;
      img.standard_mailbox.receive_size = sm.default_size;
    } else if (sm.type == od::SmType::MailboxIn) {
      img.standard_mailbox.send_offset = sm.start_address;
      img.standard_mailbox.send_size = sm.default_size;
    }
  }
  if (d.bootstrap_supported) img.bootstrap_mailbox = img.standard_mailbox;
  const auto& mb = d.mailbox;
  img.mailbox_protocols = static_cast<std::uint16_t>(
      (mb.coe ? sii::kProtoCoE : 0) | (mb.foe ? sii::kProtoFoE : 0) |
      (mb.eoe ? sii::kProtoEoE : 0) | (mb.soe ? sii::kProtoSoE : 0));
  img.size_word = static_cast<std::uint16_t>(d.esc.eeprom_bytes / sii::kBytesPerSizeUnit - 1);
  img.version = sii::kVersion;

  SiiStringTable strings;
  SiiGeneral g;
  g.order_idx = strings.add(d.identity.type_name);
  g.name_idx = strings.add(d.identity.name);
  g.group_idx = strings.add(d.identity.group_type);
  g.group_idx2 = g.group_idx;
  if (mb.coe) {
    g.coe_details = static_cast<std::uint8_t>(
        sii::kCoeEnableSdo | (mb.sdo_info ? sii::kCoeSdoInfo : 0) |
        (mb.pdo_assign ? sii::kCoePdoAssign : 0) | (mb.pdo_config ? sii::kCoePdoConfig : 0) |
        (mb.pdo_upload ? sii::kCoePdoUpload : 0) |
        (mb.complete_access ? sii::kCoeCompleteAccess : 0));
  }
  g.foe_details = mb.foe ? sii::kFoeEnable : 0;
  g.eoe_details = mb.eoe ? sii::kEoeEnable : 0;
  g.flags = d.esc.no_lrw ? sii::kFlagNotLrw : 0;
  g.physical_ports = physical_ports(d.esc.physics);
  img.general = g;

  for (auto u : d.fmmus) img.fmmus.push_back(fmmu_code(u));
  for (std::size_t i = 0; i < d.sync_managers.size(); ++i) {
    const auto& sm = d.sync_managers[i];
    SiiSyncManager s;
    s.start_address = sm.start_address;
    s.length = sm.default_size;
    const bool process_data = sm.type == od::SmType::Outputs || sm.type == od::SmType::Inputs;
    if (process_data && s.length == 0) s.length = pdo_bytes_for_sm(d, i);
    s.control = sm.control;
    s.enable = sm.enable ? sii::kSmEnable : 0;
    s.type = static_cast<std::uint8_t>(sm.type);
    img.sync_managers.push_back(s);
  }
  if (detail == SiiDetail::NoPdoDc) {
    img.strings = strings.take();
    return img;
  }
  const bool entry_names = detail == SiiDetail::Full;
  for (const auto& p : d.tx_pdos) img.tx_pdos.push_back(make_pdo(p, strings, entry_names));
  for (const auto& p : d.rx_pdos) img.rx_pdos.push_back(make_pdo(p, strings, entry_names));
  for (const auto& m : d.dc_op_modes) {
    SiiDcMode s;
    s.shift_time_sync0 = static_cast<std::uint32_t>(m.shift_time_sync0);
    s.shift_time_sync1 = static_cast<std::uint32_t>(m.shift_time_sync1);
    s.cycle_time_sync1_factor = static_cast<std::int16_t>(m.cycle_time_sync1_factor);
    s.assign_activate = m.assign_activate;
    s.cycle_time_sync0_factor = static_cast<std::int16_t>(m.cycle_time_sync0_factor);
    s.name_idx = strings.add(m.name);
    s.desc_idx = strings.add(m.description);
    img.dc_modes.push_back(s);
  }
  img.strings = strings.take();
  return img;
}

Expected<SiiOutput, std::string> write_sii_detailed(const od::DeviceDescription& device) {
  std::string first_error;
  for (auto detail : {SiiDetail::Full, SiiDetail::NoEntryNames, SiiDetail::NoPdoDc}) {
    auto bytes = encode_sii(sii_from_device(device, detail), device.esc.eeprom_bytes);
    if (bytes) return SiiOutput{std::move(*bytes), detail};
    if (bytes.error().starts_with("EEPROM size")) return fail(bytes.error());  // no level helps
    if (first_error.empty()) first_error = bytes.error();
  }
  return fail(first_error + " (also without PDO entry names and without PDO/DC categories)");
}

Expected<std::vector<std::uint8_t>, std::string> write_sii(const od::DeviceDescription& device) {
  auto out = write_sii_detailed(device);
  if (!out) return fail(out.error());
  return std::move(out->bytes);
}

}  // namespace ecat::esi
