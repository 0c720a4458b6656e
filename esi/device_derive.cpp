// Derived objects (docs/device-format.md "Derived objects"): values that
// follow from Identity, SyncManagers, Dc, PDOs and Drive are written into the
// spec as if the file had given them, unless it did. They then go through
// the same building and checks as every other object, and errors point at
// the attribute they came from.
#include <algorithm>

#include <fmt/format.h>

#include "esi/device_attrs.hpp"
#include "esi/device_build.hpp"
#include "esi/device_failure.hpp"
#include "od/device.hpp"

namespace ecat::esi {
namespace {

// CiA 301 / ETG.1000.6 §5.6.7 object indices.
constexpr std::uint16_t kDeviceType = 0x1000;
constexpr std::uint16_t kDeviceName = 0x1008;
constexpr std::uint16_t kHardwareVersion = 0x1009;
constexpr std::uint16_t kSoftwareVersion = 0x100A;
constexpr std::uint16_t kIdentity = 0x1018;
constexpr std::uint16_t kSmCommType = 0x1C00;
constexpr std::uint16_t kSmAssignFirst = 0x1C10;
constexpr std::uint16_t kSmOutputParameter = 0x1C32;
constexpr std::uint16_t kSmInputParameter = 0x1C33;
constexpr std::uint8_t kSyncModesSupportedSub = 4;
constexpr std::uint8_t kMinCycleTimeSub = 5;
// CiA 402 objects.
constexpr std::uint16_t kSupportedDriveModes = 0x6502;
constexpr std::uint16_t kSupportedHomingMethods = 0x60E3;
constexpr std::uint16_t kDriveManufacturer = 0x6504;
// 1C32h/1C33h:04 bits (coe-mailbox.md §11.3).
constexpr std::uint16_t kSyncFreeRun = 1u << 0;
constexpr std::uint16_t kSyncSm = 1u << 1;
constexpr std::uint16_t kSyncDc = 1u << 2;  // bits 3:2 = 01
constexpr std::uint8_t kMaxAssignEntries = 254;  // 1C1xh subindices 1..254
constexpr unsigned kMappingIndexShift = 16;
constexpr unsigned kMappingSubShift = 8;

Attr attr(std::string value, const Where& w) { return Attr{std::move(value), w}; }

void set_if_absent(ElementSpec& e, const std::string& name, Attr value) {
  if (!e.attrs.has(name)) e.attrs.set(name, std::move(value));
}

ObjectSpec& ensure(DeviceSpec& spec, std::uint16_t index, const Where& w,
                   std::initializer_list<std::pair<const char*, const char*>> attrs) {
  auto [it, created] = spec.objects.try_emplace(index);
  if (created) {
    it->second.where = w;
    for (const auto& [k, v] : attrs) it->second.attrs.set(k, attr(v, w));
  }
  return it->second;
}

Attr identity_attr(const DeviceSpec& spec, const char* name, const char* fallback) {
  if (const Attr* a = spec.identity.attrs.find(name)) return *a;
  return attr(fallback, spec.identity.where);
}

void derive_string(DeviceSpec& spec, std::uint16_t index, const char* object_name, const char* field) {
  const Attr* text = spec.identity.attrs.find(field);
  if (!spec.objects.contains(index) && (!text || text->value.empty())) return;
  ObjectSpec& obj = ensure(spec, index, spec.identity.where,
                           {{"name", object_name}, {"type", "VISIBLE_STRING"}, {"access", "const"}});
  if (!text || obj.attrs.has("default")) return;
  obj.attrs.set("default", *text);
  const std::string need = std::to_string(text->value.size());
  const Attr* length = obj.attrs.find("length");
  if (length && attr_unsigned(obj, "length", 0xFFFF, 0) < text->value.size()) {
    obj.attrs.set("length", attr(need, length->where));
  }
}

void derive_identity(DeviceSpec& spec) {
  const Where& w = spec.identity.where;
  ObjectSpec& dt = ensure(spec, kDeviceType, w, {{"name", "Device type"}, {"type", "UNSIGNED32"}});
  set_if_absent(dt, "default", identity_attr(spec, "deviceType", "0"));
  derive_string(spec, kDeviceName, "Device name", "name");
  derive_string(spec, kHardwareVersion, "Manufacturer hardware version", "hardwareVersion");
  derive_string(spec, kSoftwareVersion, "Manufacturer software version", "softwareVersion");

  const bool created = !spec.objects.contains(kIdentity);
  ObjectSpec& id = ensure(spec, kIdentity, w, {{"name", "Identity"}, {"code", "RECORD"}, {"type", "IDENTITY"}});
  constexpr std::array<std::pair<const char*, const char*>, 4> kFields = {{
      {"vendorId", "Vendor ID"}, {"productCode", "Product code"}, {"revision", "Revision"}, {"serial", "Serial number"}}};
  for (std::uint8_t sub = 1; sub <= kFields.size(); ++sub) {
    const auto& [field, name] = kFields[sub - 1];
    if (created) {
      ElementSpec& e = id.entries[sub];
      e.where = w;
      e.attrs.set("name", attr(name, w));
      e.attrs.set("type", attr("UNSIGNED32", w));
    }
    if (auto it = id.entries.find(sub); it != id.entries.end()) {
      set_if_absent(it->second, "default", identity_attr(spec, field, "0"));
    }
  }
}

std::string sm_type_code(const std::string& type) {
  if (type == "MailboxOut") return "1";
  if (type == "MailboxIn") return "2";
  if (type == "Outputs") return "3";
  if (type == "Inputs") return "4";
  return "0";
}

void set_access(ElementSpec& e, bool writable_in_preop, const Where& w) {
  e.attrs.set("access", attr(writable_in_preop ? "rw" : "ro", w));
  if (writable_in_preop) e.attrs.set("writeIn", attr("PreOp", w));
}

// An object the file only declares (name, type, access) and leaves the
// elements to the loader: no count and no Entry other than subindex 0.
bool declared_only(const ObjectSpec& o) {
  return !o.attrs.has("count") && std::all_of(o.entries.begin(), o.entries.end(),
                                              [](const auto& e) { return e.first == 0; });
}

// The object at `index` if the loader is to fill it: absent or declared only.
ObjectSpec* to_fill(DeviceSpec& spec, std::uint16_t index, const Where& w) {
  auto it = spec.objects.find(index);
  if (it != spec.objects.end() && !declared_only(it->second)) return nullptr;
  return &ensure(spec, index, w, {});
}

void derive_sm_types(DeviceSpec& spec) {
  const Where& w = spec.sync_managers_where;
  ObjectSpec* o = to_fill(spec, kSmCommType, w);
  if (o == nullptr) return;
  set_if_absent(*o, "name", attr("Sync manager type", w));
  set_if_absent(*o, "code", attr("ARRAY", w));
  set_if_absent(*o, "type", attr("UNSIGNED8", w));
  set_if_absent(*o, "default", attr("0", w));
  std::uint64_t count = 0;
  for (const auto& sm : *spec.sync_managers) {
    const auto n = attr_unsigned(sm, "index", 0xFF, 0) + 1;
    count = std::max(count, n);
    ElementSpec& e = o->entries[static_cast<std::uint8_t>(n)];
    e.where = sm.where;
    e.attrs.set("default", attr(sm_type_code(attr_text(sm, "type")), sm.where));
  }
  o->attrs.set("count", attr(std::to_string(count), w));
}

void derive_sm_assignment(DeviceSpec& spec, const ElementSpec& sm, bool assignable) {
  const bool outputs = attr_text(sm, "type") == "Outputs";
  const auto n = attr_unsigned(sm, "index", 0xFF, 0);
  ObjectSpec* o = to_fill(spec, static_cast<std::uint16_t>(kSmAssignFirst + n), sm.where);
  if (o == nullptr) return;
  set_if_absent(*o, "name", attr(fmt::format("Sync manager {} PDO assignment", n), sm.where));
  set_if_absent(*o, "code", attr("ARRAY", sm.where));
  set_if_absent(*o, "type", attr("UNSIGNED16", sm.where));
  set_if_absent(*o, "default", attr("0", sm.where));
  if (!o->attrs.has("access")) set_access(*o, assignable, sm.where);
  std::uint8_t sub = 0, assigned = 0;
  for (const auto& [pdo_index, pdo] : spec.pdos) {
    if (pdo.rx != outputs) continue;
    if (sub == kMaxAssignEntries) {
      fail_at(pdo.element.where, fmt::format("more than {} PDOs for SyncManager {}", kMaxAssignEntries, n));
    }
    ++sub;
    if (pdo.element.attrs.has("sm") && attr_unsigned(pdo.element, "sm", 0xFF, 0) == n) {
      ElementSpec& e = o->entries[++assigned];
      e.where = pdo.element.where;
      e.attrs.set("default", attr(fmt::format("#x{:04X}", pdo_index), pdo.element.where));
    }
  }
  o->attrs.set("count", attr(std::to_string(std::max<std::uint8_t>(sub, 1)), sm.where));
  ElementSpec& sub0 = o->entries[0];
  if (sub0.where.file.empty()) sub0.where = sm.where;
  set_if_absent(sub0, "default", attr(std::to_string(assigned), sm.where));
  if (!sub0.attrs.has("access")) {
    for (const char* a : {"access", "writeIn"}) {
      if (const Attr* declared = o->attrs.find(a)) sub0.attrs.set(a, *declared);
    }
  }
}

void derive_sm_objects(DeviceSpec& spec) {
  if (!spec.sync_managers || spec.sync_managers->empty()) return;
  derive_sm_types(spec);
  const bool assignable = attr_bool(spec.mailbox, "pdoAssign", od::MailboxProtocols{}.pdo_assign);
  for (const auto& sm : *spec.sync_managers) {
    const std::string type = attr_text(sm, "type");
    if (type == "Outputs" || type == "Inputs") derive_sm_assignment(spec, sm, assignable);
  }
}

void derive_pdo_mappings(DeviceSpec& spec) {
  const bool configurable = attr_bool(spec.mailbox, "pdoConfig", od::MailboxProtocols{}.pdo_config);
  for (const auto& [index, pdo] : spec.pdos) {
    if (spec.objects.contains(index)) continue;
    const Where& w = pdo.element.where;
    ObjectSpec& o = ensure(spec, index, w, {{"code", "RECORD"}, {"type", "PDO_MAPPING"}});
    // A PDO without a name (absent or empty: IgH's `ethercat xml` writes
    // <Name></Name>) gives its mapping object a name all the same.
    std::string name = attr_text(pdo.element, "name");
    if (name.empty()) name = fmt::format("PDO {:04X}h", index);
    o.attrs.set("name", attr(name, w));
    const bool writable = configurable && !attr_bool(pdo.element, "fixed", false);
    set_access(o, writable, w);
    const auto max_entries = attr_unsigned(pdo.element, "maxEntries", 0xFE, pdo.entries.size());
    for (std::uint64_t sub = 1; sub <= std::max<std::uint64_t>(max_entries, pdo.entries.size()); ++sub) {
      ElementSpec& e = o.entries[static_cast<std::uint8_t>(sub)];
      e.where = sub <= pdo.entries.size() ? pdo.entries[sub - 1].where : w;
      e.attrs.set("name", attr(fmt::format("SubIndex {:03d}", sub), e.where));
      e.attrs.set("type", attr("UNSIGNED32", e.where));
      std::uint64_t word = 0;
      if (sub <= pdo.entries.size()) {
        const ElementSpec& pe = pdo.entries[sub - 1];
        word = attr_unsigned(pe, "index", 0xFFFF, 0) << kMappingIndexShift |
               attr_unsigned(pe, "sub", 0xFF, 0) << kMappingSubShift | attr_unsigned(pe, "bits", 0xFF, 0);
      }
      e.attrs.set("default", attr(fmt::format("#x{:08X}", word), e.where));
    }
    ElementSpec& sub0 = o.entries[0];
    sub0.where = w;
    sub0.attrs.set("default", attr(std::to_string(pdo.entries.size()), w));
    set_access(sub0, writable, w);
  }
}

void derive_sync_parameters(DeviceSpec& spec) {
  const od::SyncLimits defaults;
  const ElementSpec& dc = spec.dc;
  std::uint16_t modes = 0;
  if (attr_bool(dc, "freeRun", defaults.free_run)) modes |= kSyncFreeRun;
  if (attr_bool(dc, "smSync", defaults.sm_synchronous)) modes |= kSyncSm;
  if (attr_bool(dc, "dcSync0", defaults.dc_sync0) || attr_bool(dc, "dcSync1", defaults.dc_sync1)) modes |= kSyncDc;
  const Attr min_cycle = dc.attrs.find("minCycleTime") ? *dc.attrs.find("minCycleTime")
                                                       : attr(std::to_string(defaults.min_cycle_time_ns), dc.where);
  for (std::uint16_t index : {kSmOutputParameter, kSmInputParameter}) {
    auto it = spec.objects.find(index);
    if (it == spec.objects.end()) continue;
    if (auto e = it->second.entries.find(kSyncModesSupportedSub); e != it->second.entries.end()) {
      set_if_absent(e->second, "default", attr(fmt::format("#x{:04X}", modes), dc.where));
    }
    if (auto e = it->second.entries.find(kMinCycleTimeSub); e != it->second.entries.end()) {
      set_if_absent(e->second, "default", min_cycle);
    }
  }
}

void derive_drive(DeviceSpec& spec) {
  if (auto it = spec.objects.find(kDriveManufacturer); it != spec.objects.end()) {
    if (spec.identity.attrs.has("vendorName")) derive_string(spec, kDriveManufacturer, "Drive manufacturer", "vendorName");
  }
  if (spec.drive.where.file.empty()) return;
  const Where& w = spec.drive.where;
  if (auto it = spec.objects.find(kSupportedDriveModes); it != spec.objects.end()) {
    set_if_absent(it->second, "default", attr(fmt::format("#x{:08X}", drive_mode_bits(spec.drive)), where_of(spec.drive, "modes")));
  }
  auto it = spec.objects.find(kSupportedHomingMethods);
  const auto methods = attr_list(spec.drive, "homingMethods");
  if (it == spec.objects.end() || methods.empty() || it->second.attrs.has("count")) return;
  ObjectSpec& o = it->second;
  for (const auto& [sub, e] : o.entries) {
    if (sub != 0) return;  // the file lists the methods itself
  }
  const Where mw = where_of(spec.drive, "homingMethods");
  o.attrs.set("count", attr(std::to_string(methods.size()), w));
  for (std::size_t i = 0; i < methods.size() && i < 0xFE; ++i) {
    ElementSpec& e = o.entries[static_cast<std::uint8_t>(i + 1)];
    e.where = mw;
    e.attrs.set("default", attr(methods[i], mw));
  }
}

}  // namespace

void derive_objects(DeviceSpec& spec) {
  derive_identity(spec);
  derive_drive(spec);  // before the axes: axis n copies 6502h and 60E3h as derived
  derive_axes(spec);   // before the PDO objects: they follow every axis' PDOs
  derive_modules(spec);  // likewise: the configured modules' PDOs join the device
  derive_sm_objects(spec);
  derive_pdo_mappings(spec);
  derive_sync_parameters(spec);
}

}  // namespace ecat::esi
