#include "esi/sii_parser.hpp"

#include <fmt/format.h>

#include "common/le.hpp"
#include "esi/sii_crc.hpp"
#include "esi/sii_layout.hpp"

namespace ecat::esi {
namespace {

using Result = Expected<void, std::string>;

std::string where(std::size_t byte_offset, std::uint16_t type) {
  return fmt::format("SII category {} at word {:04X}h", type, byte_offset / 2);
}

Result parse_strings(ConstBytes data, SiiImage& img, const std::string& at) {
  ByteReader r(data);
  const std::uint8_t n = r.u8();
  for (std::uint8_t i = 0; i < n; ++i) {
    const std::uint8_t len = r.u8();
    auto text = r.bytes(len);
    if (!r.ok()) return fail(fmt::format("{}: string {} of {} runs past the category", at, i + 1, n));
    img.strings.emplace_back(reinterpret_cast<const char*>(text.data()), text.size());
  }
  if (!r.ok()) return fail(fmt::format("{}: empty STRINGS category", at));
  return {};
}

Result parse_general(ConstBytes data, SiiImage& img, const std::string& at) {
  if (data.size() < sii::kGeneralBytes) {
    return fail(fmt::format("{}: GENERAL has {} bytes, needs {}", at, data.size(),
                            sii::kGeneralBytes));
  }
  ByteReader r(data);
  SiiGeneral g;
  g.group_idx = r.u8();
  g.image_idx = r.u8();
  g.order_idx = r.u8();
  g.name_idx = r.u8();
  g.reserved4 = r.u8();
  g.coe_details = r.u8();
  g.foe_details = r.u8();
  g.eoe_details = r.u8();
  g.soe_channels = r.u8();
  g.ds402_channels = r.u8();
  g.sysman_class = r.u8();
  g.flags = r.u8();
  g.current_on_ebus_ma = static_cast<std::int16_t>(r.u16());
  g.group_idx2 = r.u8();
  g.reserved15 = r.u8();
  g.physical_ports = r.u16();
  g.physical_memory_address = r.u16();
  img.general = g;
  return {};
}

Result parse_fmmu(ConstBytes data, SiiImage& img) {
  std::size_t n = data.size();
  while (n > 0 && data[n - 1] == sii::kFmmuPad) --n;  // padding to a whole word
  img.fmmus.insert(img.fmmus.end(), data.begin(), data.begin() + static_cast<std::ptrdiff_t>(n));
  return {};
}

Result parse_syncm(ConstBytes data, SiiImage& img, const std::string& at) {
  if (data.size() % sii::kSyncManagerBytes != 0) {
    return fail(fmt::format("{}: SYNCM length {} bytes is not a multiple of {}", at, data.size(),
                            sii::kSyncManagerBytes));
  }
  ByteReader r(data);
  while (r.remaining() > 0) {
    SiiSyncManager sm;
    sm.start_address = r.u16();
    sm.length = r.u16();
    sm.control = r.u8();
    sm.status = r.u8();
    sm.enable = r.u8();
    sm.type = r.u8();
    img.sync_managers.push_back(sm);
  }
  return {};
}

Result parse_pdos(ConstBytes data, std::vector<SiiPdo>& out, const std::string& at) {
  ByteReader r(data);
  // A trailing pad shorter than a PDO header is tolerated (odd images pad with a word).
  while (r.remaining() >= sii::kPdoHeaderBytes) {
    SiiPdo p;
    p.index = r.u16();
    const std::uint8_t n = r.u8();
    p.sync_manager = r.u8();
    p.synchronization = r.u8();
    p.name_idx = r.u8();
    p.flags = r.u16();
    for (std::uint8_t i = 0; i < n; ++i) {
      SiiPdoEntry e;
      e.index = r.u16();
      e.subindex = r.u8();
      e.name_idx = r.u8();
      e.data_type = r.u8();
      e.bit_length = r.u8();
      e.flags = r.u16();
      if (!r.ok()) {
        return fail(fmt::format("{}: PDO {:04X}h declares {} entries but the category ends "
                                "after {}",
                                at, p.index, n, i));
      }
      p.entries.push_back(e);
    }
    out.push_back(std::move(p));
  }
  return {};
}

Result parse_dc(ConstBytes data, SiiImage& img, const std::string& at) {
  if (data.size() % sii::kDcModeBytes != 0) {
    return fail(fmt::format("{}: DC length {} bytes is not a multiple of {}", at, data.size(),
                            sii::kDcModeBytes));
  }
  ByteReader r(data);
  while (r.remaining() > 0) {
    SiiDcMode m;
    m.cycle_time_sync0 = r.u32();
    m.shift_time_sync0 = r.u32();
    m.shift_time_sync1 = r.u32();
    m.cycle_time_sync1_factor = static_cast<std::int16_t>(r.u16());
    m.assign_activate = r.u16();
    m.cycle_time_sync0_factor = static_cast<std::int16_t>(r.u16());
    m.name_idx = r.u8();
    m.desc_idx = r.u8();
    for (auto& b : m.reserved) b = r.u8();
    img.dc_modes.push_back(m);
  }
  return {};
}

Result parse_category(std::uint16_t type, ConstBytes data, std::size_t offset, SiiImage& img) {
  const std::string at = where(offset, type);
  switch (static_cast<sii::CategoryType>(type)) {
    case sii::CategoryType::Strings: return parse_strings(data, img, at);
    case sii::CategoryType::General: return parse_general(data, img, at);
    case sii::CategoryType::Fmmu: return parse_fmmu(data, img);
    case sii::CategoryType::SyncM: return parse_syncm(data, img, at);
    case sii::CategoryType::TxPdo: return parse_pdos(data, img.tx_pdos, at);
    case sii::CategoryType::RxPdo: return parse_pdos(data, img.rx_pdos, at);
    case sii::CategoryType::Dc: return parse_dc(data, img, at);
    default:
      img.other_categories.push_back({type, std::vector<std::uint8_t>(data.begin(), data.end())});
      return {};
  }
}

}  // namespace

Expected<SiiImage, std::string> parse_sii(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < sii::kFixedAreaBytes) {
    return fail(fmt::format("SII image is {} bytes, shorter than the {}-byte fixed area",
                            bytes.size(), sii::kFixedAreaBytes));
  }
  SiiImage img;
  ByteReader r(bytes);
  auto& c = img.config;
  c.pdi_control = r.u16();
  c.pdi_configuration = r.u16();
  c.sync_impulse_length = r.u16();
  c.pdi_configuration2 = r.u16();
  c.station_alias = r.u16();
  c.reserved5 = r.u16();
  c.reserved6 = r.u16();
  const std::uint16_t checksum = r.u16();
  img.checksum_ok = checksum == sii::kChecksumDisabled ||
                    checksum == sii::crc8(bytes.first(sii::kConfigAreaCrcBytes));
  img.vendor_id = r.u32();
  img.product_code = r.u32();
  img.revision = r.u32();
  img.serial = r.u32();
  img.execution_delay = r.u16();
  img.port0_delay = r.u16();
  img.port1_delay = r.u16();
  r.skip(2);
  for (auto* m : {&img.bootstrap_mailbox, &img.standard_mailbox}) {
    m->receive_offset = r.u16();
    m->receive_size = r.u16();
    m->send_offset = r.u16();
    m->send_size = r.u16();
  }
  img.mailbox_protocols = r.u16();
  r.skip((sii::kWordSize - sii::kWordMailboxProtocols - 1) * 2);
  img.size_word = r.u16();
  img.version = r.u16();

  // Category walk: header (type, length in words), data, next header.
  for (;;) {
    const std::size_t offset = r.position();
    const std::uint16_t type = r.u16();
    if (!r.ok()) {
      return fail(fmt::format("SII category list runs past the end (byte {}) without an END "
                              "marker (FFFFh)",
                              offset));
    }
    if (type == static_cast<std::uint16_t>(sii::CategoryType::End)) break;
    const std::uint16_t words = r.u16();
    ConstBytes data = r.bytes(std::size_t{words} * 2);
    if (!r.ok()) {
      return fail(fmt::format("{}: length {} words runs past the end of the {}-byte image",
                              where(offset, type), words, bytes.size()));
    }
    if (auto ok = parse_category(type, data, offset, img); !ok) return fail(ok.error());
  }
  return img;
}

}  // namespace ecat::esi
