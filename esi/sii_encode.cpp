// SII encoding (ETG.2010; sii-eeprom.md §1-§3): fixed words 0..3Fh with the
// configuration-area CRC, then the categories in the order STRINGS, GENERAL,
// FMMU, SYNCM, TXPDO, RXPDO, DC, raw ones, END; the rest of the EEPROM 0xFF.
#include <algorithm>

#include <fmt/format.h>

#include "common/le.hpp"
#include "esi/sii_crc.hpp"
#include "esi/sii_layout.hpp"
#include "esi/sii_writer.hpp"

namespace ecat::esi {
namespace {

constexpr std::size_t kMaxEepromBytes = sii::kBytesPerSizeUnit * 0x10000;

void put_header(ByteWriter& w, sii::CategoryType type, std::size_t data_bytes) {
  w.u16(static_cast<std::uint16_t>(type));
  w.u16(static_cast<std::uint16_t>((data_bytes + 1) / 2));
}

void put_pad(ByteWriter& w, std::size_t data_bytes, std::uint8_t pad) {
  if (data_bytes % 2 != 0) w.u8(pad);
}

void put_pdos(ByteWriter& w, sii::CategoryType type, const std::vector<SiiPdo>& pdos) {
  if (pdos.empty()) return;
  std::size_t bytes = 0;
  for (const auto& p : pdos) bytes += sii::kPdoHeaderBytes + p.entries.size() * sii::kPdoEntryBytes;
  put_header(w, type, bytes);
  for (const auto& p : pdos) {
    w.u16(p.index);
    w.u8(static_cast<std::uint8_t>(p.entries.size()));
    w.u8(p.sync_manager);
    w.u8(p.synchronization);
    w.u8(p.name_idx);
    w.u16(p.flags);
    for (const auto& e : p.entries) {
      w.u16(e.index);
      w.u8(e.subindex);
      w.u8(e.name_idx);
      w.u8(e.data_type);
      w.u8(e.bit_length);
      w.u16(e.flags);
    }
  }
}

void put_general(ByteWriter& w, const SiiGeneral& g) {
  put_header(w, sii::CategoryType::General, sii::kGeneralBytes);
  for (std::uint8_t b : {g.group_idx, g.image_idx, g.order_idx, g.name_idx, g.reserved4,
                         g.coe_details, g.foe_details, g.eoe_details, g.soe_channels,
                         g.ds402_channels, g.sysman_class, g.flags}) {
    w.u8(b);
  }
  w.u16(static_cast<std::uint16_t>(g.current_on_ebus_ma));
  w.u8(g.group_idx2);
  w.u8(g.reserved15);
  w.u16(g.physical_ports);
  w.u16(g.physical_memory_address);
  w.fill(0, sii::kGeneralBytes - 0x14);  // bytes 14h..1Fh reserved
}

void put_categories(ByteWriter& w, const SiiImage& img) {
  if (!img.strings.empty()) {
    std::size_t bytes = 1;
    for (const auto& s : img.strings) bytes += 1 + std::min(s.size(), sii::kMaxStringLength);
    put_header(w, sii::CategoryType::Strings, bytes);
    w.u8(static_cast<std::uint8_t>(img.strings.size()));
    for (const auto& s : img.strings) {
      const std::size_t n = std::min(s.size(), sii::kMaxStringLength);
      w.u8(static_cast<std::uint8_t>(n));
      w.bytes(ConstBytes(reinterpret_cast<const std::uint8_t*>(s.data()), n));
    }
    put_pad(w, bytes, 0);
  }
  if (img.general) put_general(w, *img.general);
  if (!img.fmmus.empty()) {
    put_header(w, sii::CategoryType::Fmmu, img.fmmus.size());
    w.bytes(img.fmmus);
    put_pad(w, img.fmmus.size(), sii::kFmmuPad);
  }
  if (!img.sync_managers.empty()) {
    put_header(w, sii::CategoryType::SyncM, img.sync_managers.size() * sii::kSyncManagerBytes);
    for (const auto& sm : img.sync_managers) {
      w.u16(sm.start_address);
      w.u16(sm.length);
      w.u8(sm.control);
      w.u8(sm.status);
      w.u8(sm.enable);
      w.u8(sm.type);
    }
  }
  put_pdos(w, sii::CategoryType::TxPdo, img.tx_pdos);
  put_pdos(w, sii::CategoryType::RxPdo, img.rx_pdos);
  if (!img.dc_modes.empty()) {
    put_header(w, sii::CategoryType::Dc, img.dc_modes.size() * sii::kDcModeBytes);
    for (const auto& m : img.dc_modes) {
      w.u32(m.cycle_time_sync0);
      w.u32(m.shift_time_sync0);
      w.u32(m.shift_time_sync1);
      w.u16(static_cast<std::uint16_t>(m.cycle_time_sync1_factor));
      w.u16(m.assign_activate);
      w.u16(static_cast<std::uint16_t>(m.cycle_time_sync0_factor));
      w.u8(m.name_idx);
      w.u8(m.desc_idx);
      w.bytes(m.reserved);
    }
  }
  for (const auto& c : img.other_categories) {
    w.u16(c.type);
    w.u16(static_cast<std::uint16_t>((c.data.size() + 1) / 2));
    w.bytes(c.data);
    put_pad(w, c.data.size(), 0);
  }
  w.u16(static_cast<std::uint16_t>(sii::CategoryType::End));
}

}  // namespace

Expected<std::vector<std::uint8_t>, std::string> encode_sii(const SiiImage& img,
                                                            std::size_t eeprom_bytes) {
  if (eeprom_bytes < sii::kFixedAreaBytes + sii::kBytesPerSizeUnit ||
      eeprom_bytes % sii::kBytesPerSizeUnit != 0 || eeprom_bytes > kMaxEepromBytes) {
    return fail(fmt::format("EEPROM size {} bytes cannot be encoded: it must be a multiple of {} "
                            "between {} and {}",
                            eeprom_bytes, sii::kBytesPerSizeUnit,
                            sii::kFixedAreaBytes + sii::kBytesPerSizeUnit, kMaxEepromBytes));
  }
  std::vector<std::uint8_t> out(eeprom_bytes, 0xFF);
  ByteWriter w(out);
  const auto& c = img.config;
  for (std::uint16_t v : {c.pdi_control, c.pdi_configuration, c.sync_impulse_length,
                          c.pdi_configuration2, c.station_alias, c.reserved5, c.reserved6}) {
    w.u16(v);
  }
  w.u8(sii::crc8(ConstBytes(out).first(sii::kConfigAreaCrcBytes)));
  w.u8(0);
  w.u32(img.vendor_id);
  w.u32(img.product_code);
  w.u32(img.revision);
  w.u32(img.serial);
  w.u16(img.execution_delay);
  w.u16(img.port0_delay);
  w.u16(img.port1_delay);
  w.u16(0);
  for (const auto* m : {&img.bootstrap_mailbox, &img.standard_mailbox}) {
    w.u16(m->receive_offset);
    w.u16(m->receive_size);
    w.u16(m->send_offset);
    w.u16(m->send_size);
  }
  w.u16(img.mailbox_protocols);
  w.fill(0, (sii::kWordSize - sii::kWordMailboxProtocols - 1) * 2);
  w.u16(static_cast<std::uint16_t>(eeprom_bytes / sii::kBytesPerSizeUnit - 1));
  w.u16(img.version);
  put_categories(w, img);
  if (!w.ok()) {
    std::vector<std::uint8_t> big(kMaxEepromBytes);
    ByteWriter m(big);
    m.fill(0, sii::kFixedAreaBytes);
    put_categories(m, img);
    return fail(fmt::format("SII image needs {} bytes but the EEPROM holds only {} bytes",
                            m.position(), eeprom_bytes));
  }
  return out;
}

}  // namespace ecat::esi
