#include "master/sii.hpp"

namespace ecat::master {

namespace sii {
std::uint8_t config_crc(ConstBytes data) noexcept {
  constexpr std::uint8_t kPoly = 0x07;
  std::uint8_t crc = 0xFF;
  for (std::uint8_t b : data) {
    crc = static_cast<std::uint8_t>(crc ^ b);
    for (int i = 0; i < 8; ++i) {
      crc = (crc & 0x80) != 0 ? static_cast<std::uint8_t>((crc << 1) ^ kPoly) : static_cast<std::uint8_t>(crc << 1);
    }
  }
  return crc;
}
}  // namespace sii

namespace {

std::uint16_t word(ConstBytes image, std::size_t w) noexcept { return load_le<std::uint16_t>(image.data() + 2 * w); }
std::uint32_t dword(ConstBytes image, std::size_t w) noexcept { return load_le<std::uint32_t>(image.data() + 2 * w); }

Expected<void, SiiParseError> parse_strings(ConstBytes data, SiiInfo& info) {
  ByteReader r(data);
  const std::uint8_t count = r.u8();
  for (unsigned i = 0; i < count; ++i) {
    const std::uint8_t len = r.u8();
    const ConstBytes text = r.bytes(len);
    if (!r.ok()) return fail(SiiParseError::BadStrings);
    info.strings.emplace_back(text.begin(), text.end());
  }
  return {};
}

Expected<void, SiiParseError> parse_pdos(ConstBytes data, std::vector<SiiPdo>& out) {
  ByteReader r(data);
  while (r.remaining() >= sii::kPdoHeaderBytes) {
    SiiPdo pdo;
    pdo.index = r.u16();
    const std::uint8_t n = r.u8();
    pdo.sync_manager = r.u8();
    r.skip(1);  // synchronization
    pdo.name_index = r.u8();
    pdo.flags = r.u16();
    for (unsigned i = 0; i < n; ++i) {
      SiiPdoEntry e;
      e.index = r.u16();
      e.subindex = r.u8();
      e.name_index = r.u8();
      e.data_type = r.u8();
      e.bit_length = r.u8();
      r.skip(2);  // flags
      if (!r.ok()) return fail(SiiParseError::BadPdo);
      pdo.entries.push_back(e);
    }
    out.push_back(std::move(pdo));
  }
  return {};
}

}  // namespace

std::uint32_t SiiPdo::bit_length() const noexcept {
  std::uint32_t bits = 0;
  for (const auto& e : entries) bits += e.bit_length;
  return bits;
}

std::string SiiInfo::string(std::uint8_t index) const {
  if (index == 0 || index > strings.size()) return {};
  return strings[index - 1u];
}

std::string SiiInfo::device_name() const {
  if (general && general->name_index != 0) return string(general->name_index);
  return string(1);
}

std::uint32_t SiiInfo::default_pdo_bits(bool tx, std::uint8_t sm) const noexcept {
  std::uint32_t bits = 0;
  for (const auto& p : tx ? tx_pdos : rx_pdos) {
    if (p.sync_manager == sm) bits += p.bit_length();
  }
  return bits;
}

std::optional<std::size_t> sii_image_length(ConstBytes image) noexcept {
  std::size_t w = sii::kFirstCategory;
  for (;;) {
    if (2 * (w + 1) > image.size()) return std::nullopt;
    if (word(image, w) == static_cast<std::uint16_t>(sii::Category::End)) return 2 * (w + 1);
    if (2 * (w + 2) > image.size()) return std::nullopt;
    w += 2 + word(image, w + 1);
  }
}

Expected<SiiInfo, SiiParseError> parse_sii(ConstBytes image) {
  if (image.size() < sii::kFixedAreaBytes) return fail(SiiParseError::TooShort);
  SiiInfo info;
  info.pdi_control = word(image, sii::kPdiControl);
  info.station_alias = word(image, sii::kStationAlias);
  info.checksum = static_cast<std::uint8_t>(word(image, sii::kChecksum));
  info.checksum_ok = sii::config_crc(image.first(sii::kChecksumCoveredBytes)) == info.checksum;
  info.vendor_id = dword(image, sii::kVendorId);
  info.product_code = dword(image, sii::kProductCode);
  info.revision = dword(image, sii::kRevision);
  info.serial = dword(image, sii::kSerial);
  info.boot_rx_offset = word(image, sii::kBootRxMailboxOffset);
  info.boot_rx_size = word(image, sii::kBootRxMailboxOffset + 1);
  info.boot_tx_offset = word(image, sii::kBootRxMailboxOffset + 2);
  info.boot_tx_size = word(image, sii::kBootRxMailboxOffset + 3);
  info.rx_mailbox_offset = word(image, sii::kStdRxMailboxOffset);
  info.rx_mailbox_size = word(image, sii::kStdRxMailboxSize);
  info.tx_mailbox_offset = word(image, sii::kStdTxMailboxOffset);
  info.tx_mailbox_size = word(image, sii::kStdTxMailboxSize);
  info.mailbox_protocols = word(image, sii::kMailboxProtocols);
  info.size_word = word(image, sii::kSize);
  info.version = word(image, sii::kVersion);

  std::size_t w = sii::kFirstCategory;
  for (;;) {
    if (2 * (w + 1) > image.size()) return fail(SiiParseError::NoEndMarker);
    const std::uint16_t type = word(image, w);
    if (type == static_cast<std::uint16_t>(sii::Category::End)) break;
    if (2 * (w + 2) > image.size()) return fail(SiiParseError::CategoryBeyondEnd);
    const std::size_t words = word(image, w + 1);
    const std::size_t begin = 2 * (w + 2);
    if (begin + 2 * words > image.size()) return fail(SiiParseError::CategoryBeyondEnd);
    const ConstBytes data = image.subspan(begin, 2 * words);
    info.category_order.push_back(type);
    switch (static_cast<sii::Category>(type & 0x7FFF)) {
      case sii::Category::Strings:
        if (auto r = parse_strings(data, info); !r) return fail(r.error());
        break;
      case sii::Category::General: {
        if (data.size() != sii::kGeneralBytes) return fail(SiiParseError::BadGeneralSize);
        ByteReader r(data);
        SiiGeneral g;
        g.group_index = r.u8();
        g.image_index = r.u8();
        g.order_index = r.u8();
        g.name_index = r.u8();
        r.skip(1);
        g.coe_details = r.u8();
        g.foe_details = r.u8();
        g.eoe_details = r.u8();
        r.skip(3);  // SoE channels, DS402 channels, SysmanClass
        g.flags = r.u8();
        g.ebus_current_ma = static_cast<std::int16_t>(r.u16());
        r.skip(2);
        g.physical_ports = r.u16();
        g.physical_memory_address = r.u16();
        info.general = g;
        break;
      }
      case sii::Category::Fmmu:
        info.fmmu_usage.assign(data.begin(), data.end());
        break;
      case sii::Category::SyncM: {
        if (data.size() % sii::kSyncMEntryBytes != 0) return fail(SiiParseError::BadSyncMSize);
        ByteReader r(data);
        while (r.remaining() >= sii::kSyncMEntryBytes) {
          SiiSyncManager sm;
          sm.start = r.u16();
          sm.length = r.u16();
          sm.control = r.u8();
          r.skip(1);
          sm.enable = r.u8();
          sm.type = r.u8();
          info.sync_managers.push_back(sm);
        }
        break;
      }
      case sii::Category::TxPdo:
        if (auto r = parse_pdos(data, info.tx_pdos); !r) return fail(r.error());
        break;
      case sii::Category::RxPdo:
        if (auto r = parse_pdos(data, info.rx_pdos); !r) return fail(r.error());
        break;
      case sii::Category::Dc: {
        if (data.size() % sii::kDcEntryBytes != 0) return fail(SiiParseError::BadDcSize);
        ByteReader r(data);
        while (r.remaining() >= sii::kDcEntryBytes) {
          SiiDcMode m;
          m.cycle_time_sync0 = r.u32();
          m.shift_time_sync0 = r.u32();
          m.shift_time_sync1 = r.u32();
          m.sync1_cycle_factor = static_cast<std::int16_t>(r.u16());
          m.assign_activate = r.u16();
          m.sync0_cycle_factor = static_cast<std::int16_t>(r.u16());
          m.name_index = r.u8();
          r.skip(5);
          info.dc_modes.push_back(m);
        }
        break;
      }
      default:
        break;  // other categories are not needed by the master
    }
    w += 2 + words;
  }
  // FMMU usage 0xFF is padding.
  while (!info.fmmu_usage.empty() && info.fmmu_usage.back() == 0xFF) info.fmmu_usage.pop_back();
  return info;
}

}  // namespace ecat::master
