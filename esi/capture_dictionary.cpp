// The dictionary of a captured slave from SDO information (esi/capture_model.hpp):
// objects and entries as Get Object/Entry Description describe them, the
// uploaded values as defaults, the PDO mapping objects (16xxh/1Axxh) as the
// device's PDOs and the assignment objects (1C10h+n) as their SMs. What a
// device file cannot say (an unknown data type, a bit length that is not the
// type's, a value of the wrong size) is repaired or left out with a note.
#include <algorithm>

#include <fmt/format.h>

#include "common/le.hpp"
#include "esi/capture_model.hpp"
#include "esi/capture_process_objects.hpp"

namespace ecat::esi {
namespace {

constexpr std::uint8_t kCodeVar = 7, kCodeArray = 8, kCodeRecord = 9;
constexpr std::uint16_t kBitsPerByte = 8;
constexpr std::uint16_t kRxMappingFirst = 0x1600, kRxMappingLast = 0x17FF;
constexpr std::uint16_t kTxMappingFirst = 0x1A00, kTxMappingLast = 0x1BFF;
constexpr std::uint16_t kAssignFirst = 0x1C10, kAssignLast = 0x1C2F;
constexpr std::uint16_t kDeviceType = 0x1000, kHardwareVersion = 0x1009, kSoftwareVersion = 0x100A;
constexpr std::uint16_t kOutputsSyncParameter = 0x1C32, kInputsSyncParameter = 0x1C33;
constexpr std::uint8_t kSyncModesSub = 4, kMinCycleSub = 5;
constexpr std::uint32_t kSyncFreeRun = 1u << 0, kSyncSm = 1u << 1;
// 1C32h/1C33h:04 bits 4:2 say which DC modes the device supports, each bit one mode
// (bit 2 SYNC0, bit 3 SYNC1, bit 4 subordinated; KickCAT's EVS-NET-01 says 0x401F,
// all of them): SYNC0 is supported when bit 2 is set, whatever the others say.
constexpr std::uint32_t kSyncDcSync0 = 1u << 2;
constexpr std::uint16_t kAssignActivateSync1 = 0x0400;
constexpr std::uint32_t kProfileMask = 0xFFFF, kProfileDrive = 402;
constexpr std::uint16_t kSupportedModes = 0x6502, kHomingMethods = 0x60E3;
constexpr unsigned kMappingIndexShift = 16, kMappingSubShift = 8;
constexpr std::uint32_t kByteMask = 0xFF;

std::size_t bytes_of(std::uint16_t bits) { return (bits + kBitsPerByte - 1u) / kBitsPerByte; }

bool structured(od::DataType t) {
  switch (t) {
    case od::DataType::PdoMapping: case od::DataType::Identity: case od::DataType::CommandPar:
    case od::DataType::PdoParameter: case od::DataType::Enum: case od::DataType::SmSynchronisation:
    case od::DataType::Record: case od::DataType::BackupParameter: case od::DataType::ErrorSetting:
    case od::DataType::DiagnosisHistory: return true;
    default: return false;
  }
}

std::string generic_entry_name(std::uint8_t sub) { return fmt::format("SubIndex {:03}", sub); }

std::string where(std::uint16_t index, std::uint8_t sub) { return fmt::format("{:04X}h:{:02X}", index, sub); }

// One entry of the model; std::nullopt (with a note) when it cannot be represented.
std::optional<od::Entry> make_entry(std::uint16_t index, const CapturedEntry& c, std::vector<std::string>& notes) {
  od::Entry e;
  e.subindex = c.subindex;
  e.name = c.name.empty() ? generic_entry_name(c.subindex) : c.name;
  e.access.bits = static_cast<std::uint16_t>(c.access & (od::Access::kRw | od::Access::kRxPdoMappable |
                                                          od::Access::kTxPdoMappable | od::Access::kBackup |
                                                          od::Access::kSetting));
  e.type = static_cast<od::DataType>(c.data_type);
  e.bit_length = c.bit_length;
  if (od::canopen_name(e.type).empty() || structured(e.type)) {
    if (auto t = type_of_bits(c.bit_length)) {
      e.type = *t;
    } else if (c.bit_length % kBitsPerByte == 0 && c.bit_length != 0) {
      e.type = od::DataType::OctetString;
    } else {
      notes.push_back(fmt::format("{}: data type {:04X}h of {} bits has no device-file type; left out",
                                  where(index, c.subindex), c.data_type, c.bit_length));
      return std::nullopt;
    }
    notes.push_back(fmt::format("{}: data type {:04X}h unknown; captured as {} ({} bits)", where(index, c.subindex),
                                c.data_type, od::canopen_name(e.type), c.bit_length));
  }
  // An array of bytes described by its element type (KickCAT: BYTE with 4096 bits for
  // an ESI "ARRAY [0..511] OF BYTE" member) keeps its bytes as an OCTET_STRING.
  if ((e.type == od::DataType::Byte || e.type == od::DataType::Unsigned8) && c.bit_length > kBitsPerByte &&
      c.bit_length % kBitsPerByte == 0) {
    notes.push_back(fmt::format("{}: {} of {} bits; captured as OCTET_STRING", where(index, c.subindex),
                                od::canopen_name(e.type), c.bit_length));
    e.type = od::DataType::OctetString;
  }
  std::vector<std::uint8_t> value = c.value.value_or(std::vector<std::uint8_t>{});
  if (od::is_string(e.type)) {
    if (e.type == od::DataType::VisibleString) {
      while (!value.empty() && value.back() == 0) value.pop_back();  // NUL padding
    }
    if (value.size() * kBitsPerByte > e.bit_length) {
      notes.push_back(fmt::format("{}: value of {} bytes longer than the described {} bits; length taken from the value",
                                  where(index, c.subindex), value.size(), e.bit_length));
      e.bit_length = static_cast<std::uint16_t>(value.size() * kBitsPerByte);
    }
    e.default_value = std::move(value);
    return e;
  }
  const std::uint16_t fixed = od::fixed_bit_size(e.type);
  if (fixed != e.bit_length) {
    notes.push_back(fmt::format("{}: described as {} bits, {} has {}; the type's size is used", where(index, c.subindex),
                                e.bit_length, od::canopen_name(e.type), fixed));
    e.bit_length = fixed;
  }
  if (c.value && value.size() != bytes_of(e.bit_length)) {
    notes.push_back(fmt::format("{}: uploaded {} bytes for a {}-bit entry; default 0", where(index, c.subindex),
                                value.size(), e.bit_length));
    value.clear();
  }
  if (value.empty()) value.assign(bytes_of(e.bit_length), 0);
  e.default_value = std::move(value);
  return e;
}

std::optional<od::Object> make_object(const CapturedObject& c, std::vector<std::string>& notes) {
  od::Object o;
  o.index = c.index;
  o.name = c.name.empty() ? fmt::format("Object {:04X}h", c.index) : c.name;
  for (const CapturedEntry& ce : c.entries) {
    if (auto e = make_entry(c.index, ce, notes)) o.entries.push_back(std::move(*e));
  }
  std::sort(o.entries.begin(), o.entries.end(), [](const od::Entry& a, const od::Entry& b) {
    return a.subindex < b.subindex;
  });
  o.entries.erase(std::unique(o.entries.begin(), o.entries.end(),
                              [](const od::Entry& a, const od::Entry& b) { return a.subindex == b.subindex; }),
                  o.entries.end());
  if (o.entries.empty() || o.entries.front().subindex != 0) {
    notes.push_back(fmt::format("{:04X}h: no usable subindex 0; object left out", c.index));
    return std::nullopt;
  }
  std::uint8_t code = c.object_code;
  if (code != kCodeVar && code != kCodeArray && code != kCodeRecord) {
    notes.push_back(fmt::format("{:04X}h: object code {} is not VAR/ARRAY/RECORD; captured as {}", c.index, code,
                                o.entries.size() == 1 ? "VAR" : "RECORD"));
    code = o.entries.size() == 1 ? kCodeVar : kCodeRecord;
  }
  if (code == kCodeVar && o.entries.size() != 1) {
    notes.push_back(fmt::format("{:04X}h: a VAR with {} entries; captured as RECORD", c.index, o.entries.size()));
    code = kCodeRecord;
  }
  if (code == kCodeArray) {
    const od::DataType element = o.entries.size() > 1 ? o.entries[1].type : static_cast<od::DataType>(c.data_type);
    const bool same = std::all_of(o.entries.begin() + 1, o.entries.end(),
                                  [&](const od::Entry& e) { return e.type == element; });
    if (!same || o.entries.size() == 1) {
      if (!same) notes.push_back(fmt::format("{:04X}h: an ARRAY of mixed types; captured as RECORD", c.index));
      code = kCodeRecord;
    } else {
      o.type = element;
    }
  }
  if (code == kCodeVar) {
    o.code = od::ObjectCode::Var;
    o.type = o.entries.front().type;
    // The device file has one name per VAR: the object description's, unless that
    // is the generic "SubIndex 000" and the entry's is not. KickCAT answers both
    // ways: "Device Type" with an entry "SubIndex 000" for the VARs of its EEPROM
    // examples, "SubIndex 000" with an entry "Status Word" for some of its
    // ESI-built drive's.
    if (!c.name.empty() && c.name != generic_entry_name(0)) o.entries.front().name = c.name;
  } else if (code == kCodeArray) {
    o.code = od::ObjectCode::Array;
  } else {
    o.code = od::ObjectCode::Record;
    const auto t = static_cast<od::DataType>(c.data_type);
    o.type = structured(t) ? t : od::DataType::Record;
  }
  return o;
}

std::optional<std::uint64_t> number(const od::Dictionary& dict, std::uint16_t index, std::uint8_t sub) {
  const od::Entry* e = dict.find(index, sub);
  if (e == nullptr || od::is_string(e->type) || e->default_value.empty()) return std::nullopt;
  std::uint64_t v = 0;
  for (std::size_t i = e->default_value.size(); i-- > 0;) v = (v << kBitsPerByte) | e->default_value[i];
  return v;
}

std::string text(const od::Dictionary& dict, std::uint16_t index) {
  const od::Entry* e = dict.find(index, 0);
  if (e == nullptr || !od::is_string(e->type)) return {};
  return {e->default_value.begin(), e->default_value.end()};
}

bool mapping_object(std::uint16_t i) {
  return (i >= kRxMappingFirst && i <= kRxMappingLast) || (i >= kTxMappingFirst && i <= kTxMappingLast);
}

od::Pdo pdo_from_mapping(const od::Object& o, const od::Dictionary& dict, std::vector<std::string>& notes) {
  od::Pdo p;
  p.index = o.index;
  p.name = o.name;
  const od::Entry* count = o.find(0);
  p.fixed = count == nullptr || !count->access.writable();
  const auto n = number(dict, o.index, 0).value_or(0);
  for (std::uint64_t k = 1; k <= n; ++k) {
    const auto v = number(dict, o.index, static_cast<std::uint8_t>(k));
    if (!v) {
      notes.push_back(fmt::format("PDO {:04X}h: SI0 = {} but subindex {} was not read; mapping ends there", o.index, n, k));
      break;
    }
    od::PdoEntry e;
    e.index = static_cast<std::uint16_t>(*v >> kMappingIndexShift);
    e.subindex = static_cast<std::uint8_t>((*v >> kMappingSubShift) & kByteMask);
    e.bit_length = static_cast<std::uint8_t>(*v & kByteMask);
    if (const od::Entry* mapped = dict.find(e.index, e.subindex)) {
      e.name = mapped->name;
      e.type = mapped->type;
    } else if (auto t = type_of_bits(e.bit_length)) {
      e.type = *t;
    }
    if (e.index == 0) e.subindex = 0;  // a gap
    p.entries.push_back(e);
  }
  return p;
}

void assign_sms(od::DeviceDescription& d, std::vector<std::string>& notes) {
  for (std::uint16_t a = kAssignFirst; a <= kAssignLast; ++a) {
    if (d.dictionary.find(a) == nullptr) continue;
    const std::size_t sm = a - kAssignFirst;
    const auto n = number(d.dictionary, a, 0).value_or(0);
    for (std::uint64_t k = 1; k <= n; ++k) {
      const auto pdo = number(d.dictionary, a, static_cast<std::uint8_t>(k));
      if (!pdo) break;
      bool found = false;
      for (auto* list : {&d.rx_pdos, &d.tx_pdos}) {
        for (od::Pdo& p : *list) {
          if (p.index != *pdo) continue;
          found = true;
          const bool ok = sm < d.sync_managers.size() &&
                          d.sync_managers[sm].type == (p.is_rx() ? od::SmType::Outputs : od::SmType::Inputs);
          if (ok) {
            p.sm = static_cast<std::uint8_t>(sm);
          } else {
            notes.push_back(fmt::format("{:04X}h:{:02X} assigns PDO {:04X}h to SM{}, which is not its direction's SM; "
                                        "not assigned",
                                        a, k, *pdo, sm));
          }
        }
      }
      if (!found) notes.push_back(fmt::format("{:04X}h:{:02X} assigns PDO {:04X}h, which is not in the dictionary", a, k, *pdo));
    }
  }
}

void apply_identity_objects(od::DeviceDescription& d) {
  const od::Dictionary& dict = d.dictionary;
  d.identity.device_type = static_cast<std::uint32_t>(number(dict, kDeviceType, 0).value_or(0));
  d.identity.hardware_version = text(dict, kHardwareVersion);
  d.identity.software_version = text(dict, kSoftwareVersion);
  for (std::uint16_t p : {kOutputsSyncParameter, kInputsSyncParameter}) {
    const auto modes = number(dict, p, kSyncModesSub);
    if (!modes) continue;
    d.sync.free_run = (*modes & kSyncFreeRun) != 0;
    d.sync.sm_synchronous = (*modes & kSyncSm) != 0;
    d.sync.dc_sync0 = (*modes & kSyncDcSync0) != 0;
    d.sync.dc_sync1 = std::any_of(d.dc_op_modes.begin(), d.dc_op_modes.end(), [](const od::DcOpMode& m) {
      return (m.assign_activate & kAssignActivateSync1) != 0;
    });
    d.sync.min_cycle_time_ns = static_cast<std::uint32_t>(number(dict, p, kMinCycleSub).value_or(0));
    break;
  }
  if ((d.identity.device_type & kProfileMask) == kProfileDrive && dict.find(kSupportedModes) != nullptr) {
    od::DriveProfile drive;
    drive.supported_modes = static_cast<std::uint32_t>(number(dict, kSupportedModes, 0).value_or(0));
    if (const od::Object* h = dict.find(kHomingMethods)) {
      for (const od::Entry& e : h->entries) {
        if (e.subindex != 0 && e.default_value.size() == 1) drive.homing_methods.push_back(static_cast<std::int8_t>(e.default_value[0]));
      }
    }
    d.drive = std::move(drive);
  }
}

}  // namespace

void apply_dictionary(const std::vector<CapturedObject>& objects, od::DeviceDescription& d,
                      std::vector<std::string>& notes) {
  for (const CapturedObject& c : objects) {
    auto o = make_object(c, notes);
    if (!o) continue;
    if (auto ok = d.dictionary.put(std::move(*o)); !ok) notes.push_back(ok.error() + "; object left out");
  }
  for (const od::Object& o : d.dictionary.objects()) {
    if (!mapping_object(o.index) || o.code == od::ObjectCode::Var) continue;
    od::Pdo p = pdo_from_mapping(o, d.dictionary, notes);
    (p.is_rx() ? d.rx_pdos : d.tx_pdos).push_back(std::move(p));
  }
  for (auto* list : {&d.rx_pdos, &d.tx_pdos}) {
    for (const od::Pdo& p : *list) add_process_objects(p, d, notes);
  }
  assign_sms(d, notes);
  apply_identity_objects(d);
}

}  // namespace ecat::esi
