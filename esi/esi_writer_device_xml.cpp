#include "esi/esi_writer_device_xml.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <sstream>
#include <utility>

#include <fmt/format.h>
#include <pugixml.hpp>

#include "esi/esi_writer_names.hpp"
#include "esi/xml_chars.hpp"

namespace ecat::esi {
namespace {

constexpr const char* kFormatVersion = "1";
constexpr const char* kGeneratedNote =
    " Written by ecat-esigen (ecatslave) from a device model; see docs/device-format.md. ";

// CiA 402 modes in 6502h bit order (docs/device-format.md "Drive").
constexpr std::array<std::pair<int, const char*>, 10> kDriveModes = {{{0, "PP"}, {1, "VL"},
    {2, "PV"}, {3, "PT"}, {5, "HM"}, {6, "IP"}, {7, "CSP"}, {8, "CSV"}, {9, "CST"}, {10, "CSTCA"}}};

struct StructName {
  od::DataType type;
  const char* name;
};
constexpr std::array<StructName, 10> kStructNames = {{
    {od::DataType::Record, "RECORD"},
    {od::DataType::Identity, "IDENTITY"},
    {od::DataType::PdoMapping, "PDO_MAPPING"},
    {od::DataType::PdoParameter, "PDO_PARAMETER"},
    {od::DataType::CommandPar, "COMMAND_PAR"},
    {od::DataType::SmSynchronisation, "SM_SYNCHRONISATION"},
    {od::DataType::ErrorSetting, "ERROR_SETTING"},
    {od::DataType::BackupParameter, "BACKUP_PARAMETER"},
    {od::DataType::DiagnosisHistory, "DIAGNOSIS_HISTORY"},
    {od::DataType::Enum, "ENUM"},
}};

void attr(pugi::xml_node n, const char* name, const std::string& value) {
  n.append_attribute(name).set_value(value.c_str());
}
void attr_if(pugi::xml_node n, const char* name, const std::string& value) {
  if (!value.empty()) attr(n, name, value);
}
const char* boolean(bool b) { return b ? "true" : "false"; }
std::string hex(std::uint64_t v, int digits) { return fmt::format("#x{:0{}X}", v, digits); }

const char* sm_type(od::SmType t) {
  switch (t) {
    case od::SmType::MailboxOut: return "MailboxOut";
    case od::SmType::MailboxIn: return "MailboxIn";
    case od::SmType::Outputs: return "Outputs";
    case od::SmType::Inputs: return "Inputs";
    case od::SmType::Unused: break;
  }
  return "Unused";
}

const char* fmmu_usage(od::FmmuUsage u) {
  switch (u) {
    case od::FmmuUsage::Outputs: return "Outputs";
    case od::FmmuUsage::Inputs: return "Inputs";
    case od::FmmuUsage::MailboxState: return "MailboxState";
    case od::FmmuUsage::Unused: break;
  }
  return "Unused";
}

std::uint64_t le_value(const od::Value& v) {
  std::uint64_t out = 0;
  for (std::size_t i = 0; i < v.size() && i < sizeof(out); ++i) out |= std::uint64_t{v[i]} << (8 * i);
  return out;
}

// A value as the device format writes it (docs/device-format.md "Values").
std::string value_text(od::DataType t, const od::Value& v) {
  switch (t) {
    case od::DataType::Boolean: return le_value(v) ? "1" : "0";
    case od::DataType::Real32: {
      const auto bits = static_cast<std::uint32_t>(le_value(v));
      const float f = std::bit_cast<float>(bits);
      // NaN and infinities have no decimal form the loader takes: their bit pattern.
      return std::isfinite(f) ? fmt::format("{}", f) : hex(bits, 8);
    }
    case od::DataType::Real64: {
      const double d = std::bit_cast<double>(le_value(v));
      return std::isfinite(d) ? fmt::format("{}", d) : hex(le_value(v), 16);
    }
    case od::DataType::VisibleString: return std::string(v.begin(), v.end());
    case od::DataType::UnicodeString: {
      std::string s;
      for (std::size_t i = 0; i < v.size(); i += 2) s += static_cast<char>(v[i]);
      return s;
    }
    case od::DataType::OctetString:
    case od::DataType::Domain:
      return v.empty() ? std::string{} : "#x" + hex_binary(v);
    default:
      // Integers and bit types: hex of the little-endian bytes (two's complement).
      return hex(le_value(v), static_cast<int>(std::max<std::size_t>(v.size(), 1) * 2));
  }
}

std::string states(std::uint16_t bits) {
  std::string out;
  for (auto [bit, name] : {std::pair{od::Access::kReadPreOp, "PreOp"},
                           std::pair{od::Access::kReadSafeOp, "SafeOp"},
                           std::pair{od::Access::kReadOp, "Op"}}) {
    if (bits & bit) out += (out.empty() ? "" : " ") + std::string(name);
  }
  return out;
}

void access_attrs(pugi::xml_node n, const od::Access& a) {
  const std::uint16_t read = a.bits & od::Access::kReadAll;
  const std::uint16_t write = static_cast<std::uint16_t>((a.bits & od::Access::kWriteAll) >> 3);
  const char* access = a.is_const ? "const" : (read && write) ? "rw" : write ? "wo" : "ro";
  attr(n, "access", access);
  if (read && read != od::Access::kReadAll) attr(n, "readIn", states(read));
  if (write && write != od::Access::kReadAll) attr(n, "writeIn", states(write));
  const bool rx = a.rx_mappable();
  const bool tx = a.tx_mappable();
  if (rx || tx) attr(n, "pdo", rx && tx ? "rxtx" : rx ? "rx" : "tx");
  if (a.bits & od::Access::kBackup) attr(n, "backup", "true");
  if (a.bits & od::Access::kSetting) attr(n, "setting", "true");
}

void value_attrs(pugi::xml_node n, const od::Entry& e, bool with_type) {
  attr(n, "name", e.name);
  if (with_type) attr(n, "type", std::string(od::canopen_name(e.type)));
  if (od::is_string(e.type)) attr(n, "length", std::to_string(e.bit_length / 8));
  access_attrs(n, e.access);
  if (!e.default_value.empty()) attr(n, "default", value_text(e.type, e.default_value));
  if (e.has_min()) attr(n, "min", value_text(e.type, e.min_value));
  if (e.has_max()) attr(n, "max", value_text(e.type, e.max_value));
  attr_if(n, "unit", e.unit);
  attr_if(n, "description", e.description);
}

const char* struct_name(od::DataType t) {
  for (const auto& s : kStructNames) {
    if (s.type == t) return s.name;
  }
  return "RECORD";
}

void append_object(pugi::xml_node objects, const od::Object& o) {
  auto n = objects.append_child("Object");
  attr(n, "index", hex(o.index, 4));
  if (o.code == od::ObjectCode::Var) {
    value_attrs(n, o.entries.front(), true);
    attr_if(n, "description", o.entries.front().description.empty() ? o.description : std::string{});
    return;
  }
  attr(n, "name", o.name);
  // An ARRAY without elements (only subindex 0, as vendor files declare empty
  // 1C10h/1C11h) has no element type to name: written as a RECORD.
  const bool array = o.code == od::ObjectCode::Array && !od::canopen_name(o.type).empty();
  attr(n, "code", array ? "ARRAY" : "RECORD");
  attr(n, "type", array ? std::string(od::canopen_name(o.type))
                        : std::string(struct_name(o.code == od::ObjectCode::Array ? od::DataType::Record : o.type)));
  attr_if(n, "typeName", o.type_name);
  attr_if(n, "description", o.description);
  for (const auto& e : o.entries) {
    auto en = n.append_child("Entry");
    attr(en, "sub", std::to_string(e.subindex));
    value_attrs(en, e, true);
  }
}

// `dict`: the dictionary the entries map into (nullptr: a module's, not
// checked); an entry shorter than its object maps the object's low bits
// (docs/twins.md, alternative PDOs of two lengths) and says so: part="low".
void append_pdo(pugi::xml_node root, const char* element, const od::Pdo& p, const od::Dictionary* dict = nullptr) {
  auto n = root.append_child(element);
  attr(n, "index", hex(p.index, 4));
  attr(n, "name", p.name);
  if (p.sm) attr(n, "sm", std::to_string(*p.sm));
  if (p.fixed) attr(n, "fixed", "true");
  if (p.mandatory) attr(n, "mandatory", "true");
  std::string excludes;
  for (auto x : p.excludes) excludes += (excludes.empty() ? "" : " ") + hex(x, 4);
  attr_if(n, "excludes", excludes);
  for (const auto& e : p.entries) {
    auto en = n.append_child("Entry");
    attr(en, "index", hex(e.index, 4));
    attr(en, "sub", std::to_string(e.subindex));
    attr(en, "bits", std::to_string(e.bit_length));
    const od::Entry* oe = dict && e.index != 0 ? dict->find(e.index, e.subindex) : nullptr;
    if (oe && e.bit_length < oe->bit_length) attr(en, "part", "low");
    if (e.index != 0) attr_if(en, "name", e.name);
  }
}

void append_header(pugi::xml_node root, const od::DeviceDescription& d) {
  const auto& id = d.identity;
  auto n = root.append_child("Identity");
  attr(n, "vendorId", hex(id.vendor_id, 8));
  attr_if(n, "vendorName", id.vendor_name);
  attr(n, "productCode", hex(id.product_code, 8));
  attr(n, "revision", hex(id.revision, 8));
  attr(n, "serial", hex(id.serial, 8));
  attr_if(n, "name", id.name);
  attr_if(n, "type", id.type_name);
  attr_if(n, "groupType", id.group_type);
  attr_if(n, "groupName", id.group_name);
  attr(n, "deviceType", hex(id.device_type, 8));
  attr_if(n, "hardwareVersion", id.hardware_version);
  attr_if(n, "softwareVersion", id.software_version);
  std::string placeholders;
  for (const auto& p : id.placeholders) placeholders += (placeholders.empty() ? "" : " ") + p;
  attr_if(n, "placeholders", placeholders);

  const auto& e = d.esc;
  auto esc = root.append_child("Esc");
  attr(esc, "escType", hex(e.esc_type, 2));
  attr(esc, "escRevision", hex(e.revision, 2));
  attr(esc, "build", hex(e.build, 4));
  attr(esc, "ramSize", std::to_string(e.process_ram_bytes));
  attr(esc, "eepromSize", std::to_string(e.eeprom_bytes));
  attr(esc, "fmmus", std::to_string(e.fmmu_count));
  attr(esc, "syncManagers", std::to_string(e.sm_count));
  attr(esc, "dc", boolean(e.dc_supported));
  attr(esc, "dc64", boolean(e.dc_64bit));
  attr(esc, "noLrw", boolean(e.no_lrw));
  attr(esc, "noReadWrite", boolean(e.no_read_write));
  attr(esc, "pdiControl", hex(e.pdi_control, 4));
  attr(esc, "pdiConfiguration", hex(e.pdi_configuration, 4));
  attr(esc, "pdiConfiguration2", hex(e.pdi_configuration2, 4));
  attr(esc, "syncImpulseLength", std::to_string(e.sync_impulse_length));
  attr(esc, "alias", std::to_string(e.configured_station_alias));
  attr(esc, "bootstrap", boolean(d.bootstrap_supported));
  if (e.physics != "YY") attr(esc, "physics", e.physics);  // two MII ports: the default

  const auto& m = d.mailbox;
  auto mb = root.append_child("Mailbox");
  attr(mb, "coe", boolean(m.coe));
  attr(mb, "foe", boolean(m.foe));
  attr(mb, "eoe", boolean(m.eoe));
  attr(mb, "soe", boolean(m.soe));
  attr(mb, "sdoInfo", boolean(m.sdo_info));
  attr(mb, "pdoAssign", boolean(m.pdo_assign));
  attr(mb, "pdoConfig", boolean(m.pdo_config));
  attr(mb, "completeAccess", boolean(m.complete_access));
  attr(mb, "segmentedSdo", boolean(m.segmented_sdo));
  attr(mb, "pdoUpload", boolean(m.pdo_upload));
}

void append_layout(pugi::xml_node root, const od::DeviceDescription& d) {
  auto sms = root.append_child("SyncManagers");
  for (std::size_t i = 0; i < d.sync_managers.size(); ++i) {
    const auto& sm = d.sync_managers[i];
    if (sm.type == od::SmType::Unused && sm.start_address == 0) continue;
    auto n = sms.append_child("Sm");
    attr(n, "index", std::to_string(i));
    attr(n, "type", sm_type(sm.type));
    attr(n, "start", hex(sm.start_address, 4));
    if (sm.default_size) attr(n, "size", std::to_string(sm.default_size));
    if (sm.min_size) attr(n, "minSize", std::to_string(sm.min_size));
    if (sm.max_size) attr(n, "maxSize", std::to_string(sm.max_size));
    attr(n, "control", hex(sm.control, 2));
    attr(n, "enable", boolean(sm.enable));
  }
  auto fmmus = root.append_child("Fmmus");
  for (auto u : d.fmmus) attr(fmmus.append_child("Fmmu"), "usage", fmmu_usage(u));
  auto dc = root.append_child("Dc");
  attr(dc, "minCycleTime", std::to_string(d.sync.min_cycle_time_ns));
  attr(dc, "maxCycleTime", std::to_string(d.sync.max_cycle_time_ns));
  attr(dc, "freeRun", boolean(d.sync.free_run));
  attr(dc, "smSync", boolean(d.sync.sm_synchronous));
  attr(dc, "dcSync0", boolean(d.sync.dc_sync0));
  attr(dc, "dcSync1", boolean(d.sync.dc_sync1));
  for (const auto& m : d.dc_op_modes) {
    auto n = dc.append_child("OpMode");
    attr(n, "name", m.name);
    attr_if(n, "desc", m.description);
    attr(n, "assignActivate", hex(m.assign_activate, 4));
    attr(n, "cycleTimeSync0Factor", std::to_string(m.cycle_time_sync0_factor));
    attr(n, "shiftTimeSync0", std::to_string(m.shift_time_sync0));
    attr(n, "cycleTimeSync1Factor", std::to_string(m.cycle_time_sync1_factor));
    attr(n, "shiftTimeSync1", std::to_string(m.shift_time_sync1));
  }
}

void append_drive(pugi::xml_node root, const od::DriveProfile& drive) {
  auto n = root.append_child("Drive");
  std::string modes;
  for (auto [bit, name] : kDriveModes) {
    if (drive.supported_modes & (1u << bit)) modes += (modes.empty() ? "" : " ") + std::string(name);
  }
  attr_if(n, "modes", modes);
  std::string homing;
  for (auto m : drive.homing_methods) homing += (homing.empty() ? "" : " ") + std::to_string(m);
  attr_if(n, "homingMethods", homing);
  for (const auto& [name, value] : drive.plant) {
    auto p = n.append_child("Plant");
    attr(p, "name", name);
    attr(p, "value", fmt::format("{}", value));
  }
  // Several axes (docs/device-format.md "Several axes"): the layout, so the
  // loader binds each axis to its objects; the objects and PDOs of every axis
  // are written as objects and PDOs, which the loader keeps as written.
  const od::AxisLayout& l = drive.axes;
  if (l.axes <= 1) return;
  attr(n, "axes", std::to_string(l.axes));
  attr(n, "axisIndexOffset", hex(l.index_offset, 4));
  attr(n, "axisPdoOffset", hex(l.pdo_offset, 4));
  const od::AxisLayout defaults;
  const bool default_ranges = l.ranges.size() == defaults.ranges.size() &&
                              l.ranges.front().first == defaults.ranges.front().first &&
                              l.ranges.front().last == defaults.ranges.front().last;
  if (!default_ranges) {
    for (const od::AxisRange& r : l.ranges) {
      auto a = n.append_child("AxisObjects");
      attr(a, "from", hex(r.first, 4));
      attr(a, "to", hex(r.last, 4));
    }
  }
  for (const od::AxisIndex& x : l.exceptions) {
    auto a = n.append_child("AxisIndex");
    attr(a, "index", hex(x.index, 4));
    attr(a, "axis", std::to_string(x.axis));
    attr(a, "at", hex(x.at, 4));
  }
}

// <Modules>: the module types at their slot-0 indices, the slot rules and the
// configured modules as Plug elements (docs/device-format.md "Modular devices").
void append_modules(pugi::xml_node root, const od::ModularDevice& m) {
  auto n = root.append_child("Modules");
  attr(n, "indexIncrement", hex(m.index_increment, 4));
  attr(n, "pdoIncrement", std::to_string(m.pdo_increment));
  attr(n, "downloadIdentList", boolean(m.download_ident_list));
  for (const od::ModuleType& t : m.types) {
    auto mod = n.append_child("Module");
    attr(mod, "ident", hex(t.ident, 8));
    attr_if(mod, "type", t.type);
    attr_if(mod, "name", t.name);
    attr_if(mod, "class", t.module_class);
    if (t.profile != 0) attr(mod, "profile", hex(t.profile, 8));
    if (!t.objects.empty()) {
      auto objects = mod.append_child("Objects");
      for (const auto& o : t.objects) append_object(objects, o);
    }
    for (const auto* list : {&t.rx_pdos, &t.tx_pdos}) {
      for (const auto& p : *list) append_pdo(mod, p.is_rx() ? "RxPdo" : "TxPdo", p);
    }
  }
  for (const od::SlotRule& r : m.slots) {
    auto slot = n.append_child("Slot");
    attr_if(slot, "name", r.name);
    attr(slot, "min", std::to_string(r.min_instances));
    attr(slot, "max", std::to_string(r.max_instances));
    std::string idents;
    for (std::uint32_t i : r.idents) idents += (idents.empty() ? "" : " ") + hex(i, 8);
    attr(slot, "modules", idents);
    if (r.default_ident) attr(slot, "default", hex(*r.default_ident, 8));
  }
  for (std::uint32_t ident : m.configured) attr(n.append_child("Plug"), "module", hex(ident, 8));
}

}  // namespace

std::string write_device_xml(const od::DeviceDescription& d) {
  pugi::xml_document doc;
  auto decl = doc.append_child(pugi::node_declaration);
  decl.append_attribute("version").set_value("1.0");
  decl.append_attribute("encoding").set_value("UTF-8");
  doc.append_child(pugi::node_comment).set_value(kGeneratedNote);
  auto root = doc.append_child("Device");
  attr(root, "formatVersion", kFormatVersion);
  append_header(root, d);
  append_layout(root, d);
  auto objects = root.append_child("Objects");
  // A configured module's objects and PDOs are written once, in its module type.
  const od::ModularDevice* m = d.modular ? &*d.modular : nullptr;
  for (const auto& o : d.dictionary.objects()) {
    if (!m || !m->placed_object(o.index)) append_object(objects, o);
  }
  for (const auto* list : {&d.rx_pdos, &d.tx_pdos}) {
    for (const auto& p : *list) {
      if (!m || !m->placed_pdo(p.index)) append_pdo(root, p.is_rx() ? "RxPdo" : "TxPdo", p, &d.dictionary);
    }
  }
  if (d.drive) append_drive(root, *d.drive);
  if (m) append_modules(root, *m);
  // The last guard of issue 32 item 1 (c): no character XML 1.0 forbids.
  make_xml_safe(doc);
  std::ostringstream out;
  doc.save(out, "  ", pugi::format_indent, pugi::encoding_utf8);
  return out.str();
}

}  // namespace ecat::esi
