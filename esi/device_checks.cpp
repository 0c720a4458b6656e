// PDOs and sync manager memory (docs/device-format.md "Checks"): PDO entries
// must name existing, mappable objects of the right size (ETG.1000.6
// §5.6.7.4.7); PDOs must fit their SM; SM buffers (three of them in buffered
// mode, ESC datasheet section I "SyncManager") must lie in process RAM
// without overlapping.
#include <algorithm>

#include <fmt/format.h>

#include "esi/device_attrs.hpp"
#include "esi/device_build.hpp"
#include "esi/device_failure.hpp"
#include "esi/device_parse.hpp"

namespace ecat::esi {
namespace {

constexpr std::uint16_t kRxPdoFirst = 0x1600, kRxPdoLast = 0x17FF;
constexpr std::uint16_t kTxPdoFirst = 0x1A00, kTxPdoLast = 0x1BFF;
constexpr std::uint64_t kMaxPdoEntries = 254;  // mapping subindices 1..254
constexpr std::uint64_t kMaxEntryBits = 0xFF;
constexpr std::uint32_t kProcessRamStart = 0x1000;
constexpr std::uint8_t kSmModeMask = 0x03;     // control bits 1:0
constexpr std::uint8_t kSmModeBuffered = 0x00;  // three buffers
constexpr std::uint32_t kBufferedCopies = 3;
constexpr std::uint32_t kWatchdogOnlyLength = 1;  // SM length 1: no buffers (Section II 0x0802)
constexpr std::uint32_t kDigitalOutputFirst = 0x0F00, kDigitalOutputEnd = 0x0F04;  // ESC digital output data register
constexpr std::uint32_t kBitsPerByte = 8;

std::uint32_t bytes_of(std::uint32_t bits) { return (bits + kBitsPerByte - 1) / kBitsPerByte; }

od::SmType sm_type_for(bool rx) { return rx ? od::SmType::Outputs : od::SmType::Inputs; }

od::PdoEntry build_pdo_entry(const PdoSpec& pdo, const ElementSpec& e, const od::Dictionary& dict) {
  od::PdoEntry out;
  out.index = static_cast<std::uint16_t>(attr_unsigned(e, "index", 0xFFFF, 0));
  out.subindex = static_cast<std::uint8_t>(attr_unsigned(e, "sub", 0xFF, 0));
  out.bit_length = static_cast<std::uint8_t>(attr_unsigned(e, "bits", kMaxEntryBits, 0));
  out.name = attr_text(e, "name");
  const std::string what = fmt::format("PDO {} entry {}", object_name(pdo.index),
                                       entry_name(out.index, out.subindex));
  if (out.index == 0) {
    if (out.subindex != 0) fail_at(e.where, fmt::format("{}: a gap must have subindex 0", what));
    if (out.bit_length == 0) fail_at(e.where, fmt::format("{}: a gap needs bits > 0", what));
    return out;
  }
  const od::Entry* entry = dict.find(out.index, out.subindex);
  if (entry == nullptr) {
    fail_at(e.where, fmt::format("{}: no such {}", what, dict.find(out.index) ? "subindex" : "object"));
  }
  const bool ok = pdo.rx ? entry->access.rx_mappable() : entry->access.tx_mappable();
  if (!ok) {
    fail_at(e.where, fmt::format("{}: {} is not {}-mappable", what, entry_name(out.index, out.subindex),
                                 pdo.rx ? "RxPDO" : "TxPDO"));
  }
  // part="low": the entry maps the low bits of a longer integer object (an
  // alternative PDO of a shorter length, Beckhoff EJ2521's 16-bit PDO of the
  // 32-bit 7000h:12; docs/twins.md). Little-endian, so the first bytes.
  const std::string part = attr_text(e, "part");
  if (!part.empty() && part != "low") fail_at(where_of(e, "part"), fmt::format("{}: part '{}' is not 'low'", what, part));
  const bool low_part = part == "low" && out.bit_length < entry->bit_length && !od::is_string(entry->type);
  if (part == "low" && !low_part) {
    fail_at(where_of(e, "part"), fmt::format("{}: part=\"low\" needs fewer bits ({}) than the integer object's {}", what,
                                             out.bit_length, entry->bit_length));
  }
  if (out.bit_length != entry->bit_length && !low_part) {
    fail_at(where_of(e, "bits"), fmt::format("{}: bits {} differ from the object's size ({} bits)", what,
                                             out.bit_length, entry->bit_length));
  }
  if (out.name.empty()) out.name = entry->name;
  out.type = entry->type;
  return out;
}

od::Pdo build_pdo(const PdoSpec& spec, od::DeviceDescription& dev) {
  const ElementSpec& e = spec.element;
  const auto [first, last] = spec.rx ? std::pair{kRxPdoFirst, kRxPdoLast} : std::pair{kTxPdoFirst, kTxPdoLast};
  if (spec.index < first || spec.index > last) {
    fail_at(where_of(e, "index"), fmt::format("{} index {} is outside {:04X}h..{:04X}h",
                                              spec.rx ? "RxPdo" : "TxPdo", object_name(spec.index), first, last));
  }
  od::Pdo pdo;
  pdo.index = spec.index;
  pdo.name = attr_text(e, "name");
  pdo.fixed = attr_bool(e, "fixed", false);
  pdo.mandatory = attr_bool(e, "mandatory", false);
  pdo.source_line = e.where.line;
  if (e.attrs.has("sm")) {
    const auto sm = attr_unsigned(e, "sm", 0xFF, 0);
    if (sm >= dev.sync_managers.size() || dev.sync_managers[sm].type != sm_type_for(spec.rx)) {
      fail_at(where_of(e, "sm"), fmt::format("PDO {}: SyncManager {} is not an {} SyncManager",
                                             object_name(spec.index), sm, spec.rx ? "Outputs" : "Inputs"));
    }
    pdo.sm = static_cast<std::uint8_t>(sm);
  }
  for (const auto& x : attr_list(e, "excludes")) {
    ElementSpec one;
    one.attrs.set("excludes", Attr{x, where_of(e, "excludes")});
    pdo.excludes.push_back(static_cast<std::uint16_t>(attr_unsigned(one, "excludes", 0xFFFF, 0)));
  }
  const auto max_entries = attr_unsigned(e, "maxEntries", kMaxPdoEntries, spec.entries.size());
  if (spec.entries.size() > max_entries) {
    fail_at(where_of(e, "maxEntries"), fmt::format("PDO {} has {} entries, more than maxEntries {}",
                                                   object_name(spec.index), spec.entries.size(), max_entries));
  }
  for (const auto& entry : spec.entries) pdo.entries.push_back(build_pdo_entry(spec, entry, dev.dictionary));
  return pdo;
}

// The SM a PDO would be placed in: its default SM, else the first SM of its direction.
std::optional<std::size_t> sm_of(const od::Pdo& pdo, const od::DeviceDescription& dev) {
  if (pdo.sm) return *pdo.sm;
  for (std::size_t i = 0; i < dev.sync_managers.size(); ++i) {
    if (dev.sync_managers[i].type == sm_type_for(pdo.is_rx())) return i;
  }
  return std::nullopt;
}

std::uint32_t assigned_bytes(const od::DeviceDescription& dev, std::size_t sm) {
  std::uint32_t bits = 0;
  for (const auto* list : {&dev.rx_pdos, &dev.tx_pdos}) {
    for (const auto& p : *list) {
      if (p.sm && *p.sm == sm) bits += p.bit_length();
    }
  }
  return bytes_of(bits);
}

void check_pdo_sizes(const DeviceSpec& spec, const od::DeviceDescription& dev) {
  std::vector<std::uint32_t> bits(dev.sync_managers.size(), 0);
  for (const auto* list : {&dev.rx_pdos, &dev.tx_pdos}) {
    for (const auto& p : *list) {
      auto sm = sm_of(p, dev);
      if (!sm) continue;
      const auto& cfg = dev.sync_managers[*sm];
      const std::uint32_t limit = cfg.max_size ? cfg.max_size : cfg.default_size;
      const Where& w = spec.pdos.at(p.index).element.where;
      if (limit && bytes_of(p.bit_length()) > limit) {
        fail_at(w, fmt::format("PDO {} is {} bytes, longer than SyncManager {}'s maximum {}",
                               object_name(p.index), bytes_of(p.bit_length()), *sm, limit));
      }
      if (!p.sm) continue;
      bits[*sm] += p.bit_length();
      if (limit && bytes_of(bits[*sm]) > limit) {
        fail_at(w, fmt::format("PDOs assigned to SyncManager {} need {} bytes, more than its maximum {}",
                               *sm, bytes_of(bits[*sm]), limit));
      }
    }
  }
}

Where sm_where(const DeviceSpec& spec, std::size_t index) {
  for (const auto& e : *spec.sync_managers) {
    if (attr_unsigned(e, "index", 0xFF, 0) == index) return e.where;
  }
  return spec.sync_managers_where;
}

}  // namespace

od::Pdo build_module_pdo(const PdoSpec& spec, od::DeviceDescription& dev) { return build_pdo(spec, dev); }

void build_pdos(const DeviceSpec& spec, od::DeviceDescription& dev) {
  for (const auto& [index, p] : spec.pdos) {
    (p.rx ? dev.rx_pdos : dev.tx_pdos).push_back(build_pdo(p, dev));
  }
  for (const auto* list : {&dev.rx_pdos, &dev.tx_pdos}) {
    for (const auto& p : *list) {
      for (std::uint16_t x : p.excludes) {
        if (!spec.pdos.contains(x)) {
          fail_at(where_of(spec.pdos.at(p.index).element, "excludes"),
                  fmt::format("PDO {} excludes PDO {}, which is not defined", object_name(p.index), object_name(x)));
        }
      }
    }
  }
  check_pdo_sizes(spec, dev);
}

void check_sync_manager_memory(const DeviceSpec& spec, const od::DeviceDescription& dev) {
  struct Range {
    std::size_t sm;
    std::uint32_t first, end;  // [first, end)
  };
  std::vector<Range> ranges;
  const std::uint32_t ram_end = kProcessRamStart + dev.esc.process_ram_bytes;
  for (std::size_t i = 0; i < dev.sync_managers.size(); ++i) {
    const auto& sm = dev.sync_managers[i];
    if (sm.type == od::SmType::Unused) continue;
    // A mailbox SM is configured with its default size (SII words 18h-1Bh);
    // vendor files give a MaxSize that would overlap the next mailbox SM.
    const bool mailbox = sm.type == od::SmType::MailboxOut || sm.type == od::SmType::MailboxIn;
    std::uint32_t length = (sm.max_size && !(mailbox && sm.default_size)) ? sm.max_size : sm.default_size;
    if (length == 0) length = assigned_bytes(dev, i);
    // Devices without a µC (Beckhoff EL2xxx, EK18xx, EP2xxx) put their
    // outputs SM on the ESC's digital output register 0x0F00-0x0F03, which the
    // FMMU writes bit by bit (ESC Section II 0x0F00; SII of an EL2004: SM
    // 0x0F00, control 0x44): one register, no buffer copies in process RAM.
    const bool digital_output = sm.start_address >= kDigitalOutputFirst &&
                                sm.start_address + std::max<std::uint32_t>(length, 1) <= kDigitalOutputEnd;
    // ESC Section II 0x0802: a length of 1 does not activate the SM ("only
    // Watchdog Trigger is generated"): its byte is plain memory, no three
    // buffers. Beckhoff EQ2339 puts 1-byte input SMs at 1000h and 1001h, in
    // "3-buffer" mode, on the digital inputs the ESC's digital I/O PDI writes.
    const bool one_byte = length == kWatchdogOnlyLength;
    if ((sm.control & kSmModeMask) == kSmModeBuffered && !digital_output && !one_byte) length *= kBufferedCopies;
    const Range r{i, sm.start_address, sm.start_address + length};
    const Where w = sm_where(spec, i);
    if (!digital_output && (r.first < kProcessRamStart || r.end > ram_end)) {
      fail_at(w, fmt::format("SyncManager {} ({:#06x}..{:#06x}) is outside the process RAM {:#06x}..{:#06x}",
                             i, r.first, r.end - 1, kProcessRamStart, ram_end - 1));
    }
    for (const auto& o : ranges) {
      if (r.first < o.end && o.first < r.end && length > 0) {
        fail_at(w, fmt::format("SyncManager {} ({:#06x}..{:#06x}) overlaps SyncManager {} ({:#06x}..{:#06x})",
                               i, r.first, r.end - 1, o.sm, o.first, o.end - 1));
      }
    }
    ranges.push_back(r);
  }
}

}  // namespace ecat::esi
