// Object and entry building (docs/device-format.md "Objects"): types,
// access, default/min/max values with their range checks, generated
// subindex 0 of ARRAY/RECORD (CiA 301 §7.4.3: "highest sub-index supported").
#include <algorithm>
#include <array>
#include <utility>

#include <fmt/format.h>

#include "esi/device_attrs.hpp"
#include "esi/device_build.hpp"
#include "esi/device_failure.hpp"
#include "esi/device_parse.hpp"
#include "esi/device_values.hpp"

namespace ecat::esi {
namespace {

using od::DataType;

constexpr std::uint16_t kMaxStringLength = 0xFFFF / 8;
constexpr std::string_view kNumberOfEntries = "Number of entries";

constexpr std::array<std::pair<std::string_view, DataType>, 10> kStructuredTypes = {{
    {"RECORD", DataType::Record},
    {"IDENTITY", DataType::Identity},
    {"PDO_MAPPING", DataType::PdoMapping},
    {"PDO_PARAMETER", DataType::PdoParameter},
    {"COMMAND_PAR", DataType::CommandPar},
    {"SM_SYNCHRONISATION", DataType::SmSynchronisation},
    {"ERROR_SETTING", DataType::ErrorSetting},
    {"BACKUP_PARAMETER", DataType::BackupParameter},
    {"DIAGNOSIS_HISTORY", DataType::DiagnosisHistory},
    {"ENUM", DataType::Enum},
}};

// Attributes an ARRAY element / RECORD entry takes from its object.
constexpr std::array<std::string_view, 10> kArrayInherited = {
    "type", "access", "readIn", "writeIn", "pdo", "backup", "setting", "default", "min", "max"};
constexpr std::array<std::string_view, 6> kRecordInherited = {"access", "readIn", "writeIn",
                                                              "pdo",    "backup", "setting"};

template <std::size_t N>
ElementSpec layered(const ObjectSpec& obj, const std::array<std::string_view, N>& inherited,
                    const ElementSpec* entry) {
  ElementSpec out;
  out.where = entry ? entry->where : obj.where;
  for (auto name : inherited) {
    if (const Attr* a = obj.attrs.find(name)) out.attrs.set(std::string(name), *a);
  }
  if (const Attr* u = obj.attrs.find("unit")) out.attrs.set("unit", *u);
  if (entry) out.attrs.merge(entry->attrs);
  return out;
}

std::uint16_t state_bits(const ElementSpec& e, std::string_view attr, bool write) {
  std::uint16_t bits = 0;
  for (const auto& s : attr_list(e, attr)) {
    if (s == "PreOp") bits |= write ? od::Access::kWritePreOp : od::Access::kReadPreOp;
    else if (s == "SafeOp") bits |= write ? od::Access::kWriteSafeOp : od::Access::kReadSafeOp;
    else if (s == "Op") bits |= write ? od::Access::kWriteOp : od::Access::kReadOp;
    else fail_at(where_of(e, attr), fmt::format("unknown ESM state '{}' in {}", s, attr));
  }
  return bits;
}

od::Access parse_access(const ElementSpec& e) {
  od::Access acc;
  const std::string a = attr_text(e, "access", "ro");
  if (a == "ro") acc.bits = od::Access::kRo;
  else if (a == "rw") acc.bits = od::Access::kRw;
  else if (a == "wo") acc.bits = od::Access::kWo;
  else if (a == "const") { acc.bits = od::Access::kRo; acc.is_const = true; }
  else fail_at(where_of(e, "access"), fmt::format("unknown access '{}' (ro, rw, wo, const)", a));
  if (e.attrs.has("readIn")) {
    acc.bits = static_cast<std::uint16_t>((acc.bits & ~od::Access::kReadAll) | state_bits(e, "readIn", false));
  }
  if (e.attrs.has("writeIn")) {
    acc.bits = static_cast<std::uint16_t>((acc.bits & ~od::Access::kWriteAll) | state_bits(e, "writeIn", true));
  }
  const std::string pdo = attr_text(e, "pdo", "none");
  if (pdo == "rx" || pdo == "rxtx") acc.bits |= od::Access::kRxPdoMappable;
  if (pdo == "tx" || pdo == "rxtx") acc.bits |= od::Access::kTxPdoMappable;
  if (attr_bool(e, "backup", false)) acc.bits |= od::Access::kBackup;
  if (attr_bool(e, "setting", false)) acc.bits |= od::Access::kSetting;
  return acc;
}

DataType resolve_type(const ElementSpec& e, std::optional<DataType> forced, const std::string& what) {
  const Attr* t = e.attrs.find("type");
  if (!t) {
    if (forced) return *forced;
    fail_at(e.where, fmt::format("{} has no type", what));
  }
  auto type = od::from_canopen_name(t->value);
  if (!type) fail_at(t->where, fmt::format("unknown data type '{}'", t->value));
  if (forced && *type != *forced) {
    fail_at(t->where, fmt::format("{} has type {} but must be {}", what, t->value,
                                  od::canopen_name(*forced)));
  }
  return *type;
}

od::Value value_of(const ElementSpec& e, std::string_view attr, const od::Entry& entry,
                   const std::string& what) {
  const Attr* a = e.attrs.find(attr);
  if (!a) return {};
  if (attr != "default" && !is_numeric(entry.type)) {
    fail_at(a->where, fmt::format("{} {}: {} has no {}", what, attr, od::canopen_name(entry.type), attr));
  }
  auto v = encode_value(entry.type, entry.bit_length, a->value);
  if (!v) fail_at(a->where, fmt::format("{} {}: {}", what, attr, v.error()));
  return std::move(*v);
}

od::Entry build_entry(std::uint16_t index, std::uint8_t sub, const ElementSpec& e,
                      std::optional<DataType> forced, std::string default_name) {
  const std::string what = entry_name(index, sub);
  od::Entry entry;
  entry.subindex = sub;
  entry.name = attr_text(e, "name", default_name);
  entry.type = resolve_type(e, forced, what);
  entry.source_line = e.where.line;
  if (od::is_string(entry.type)) {
    std::uint64_t length = 0;
    if (e.attrs.has("length")) {
      length = attr_unsigned(e, "length", kMaxStringLength, 0);
    } else if (e.attrs.has("bits")) {
      length = attr_unsigned(e, "bits", 0xFFFF, 0) / 8;
    } else {
      const std::size_t chars = attr_text(e, "default").size();
      length = entry.type == DataType::UnicodeString ? 2 * chars
               : entry.type == DataType::VisibleString ? chars
                                                        : (chars + 1) / 2;
    }
    entry.bit_length = entry_bit_length(entry.type, static_cast<std::uint32_t>(length));
  } else {
    entry.bit_length = od::fixed_bit_size(entry.type);
    if (entry.bit_length == 0) {
      fail_at(where_of(e, "type"), fmt::format("{}: type {} cannot be used for a value", what,
                                               od::canopen_name(entry.type)));
    }
  }
  if (e.attrs.has("bits")) {
    const auto bits = attr_unsigned(e, "bits", 0xFFFF, 0);
    if (bits != entry.bit_length) {
      fail_at(where_of(e, "bits"), fmt::format("{}: bits {} does not match the size of {} ({} bits)",
                                               what, bits, od::canopen_name(entry.type), entry.bit_length));
    }
  }
  entry.access = parse_access(e);
  entry.default_value = value_of(e, "default", entry, what);
  if (!e.attrs.has("default")) entry.default_value = zero_value(entry.type, entry.bit_length);
  entry.min_value = value_of(e, "min", entry, what);
  entry.max_value = value_of(e, "max", entry, what);
  if (entry.has_min() && entry.has_max() && compare_values(entry.type, entry.min_value, entry.max_value) > 0) {
    fail_at(where_of(e, "min"), fmt::format("{}: min {} is above max {}", what, attr_text(e, "min"),
                                            attr_text(e, "max")));
  }
  if (entry.has_min() && compare_values(entry.type, entry.default_value, entry.min_value) < 0) {
    fail_at(where_of(e, "default"), fmt::format("{}: default {} is below min {}", what,
                                                attr_text(e, "default", "0"), attr_text(e, "min")));
  }
  if (entry.has_max() && compare_values(entry.type, entry.default_value, entry.max_value) > 0) {
    fail_at(where_of(e, "default"), fmt::format("{}: default {} is above max {}", what,
                                                attr_text(e, "default", "0"), attr_text(e, "max")));
  }
  entry.unit = attr_text(e, "unit");
  entry.description = attr_text(e, "description");
  return entry;
}

od::Entry build_sub0(std::uint16_t index, const ObjectSpec& obj, std::uint8_t highest) {
  ElementSpec e;
  e.where = obj.where;
  auto it = obj.entries.find(0);
  if (it != obj.entries.end()) e = it->second;
  if (!e.attrs.has("default")) e.attrs.set("default", Attr{std::to_string(highest), e.where});
  return build_entry(index, 0, e, DataType::Unsigned8, std::string(kNumberOfEntries));
}

std::string array_element_name(std::uint8_t sub) { return fmt::format("SubIndex {:03d}", sub); }

void build_array(std::uint16_t index, const ObjectSpec& obj, od::Object& out) {
  out.type = resolve_type(obj, std::nullopt, object_name(index));
  const std::uint8_t highest = obj.entries.empty() ? 0 : obj.entries.rbegin()->first;
  const auto count = static_cast<std::uint8_t>(attr_unsigned(obj, "count", 0xFF, highest));
  if (highest > count) {
    fail_at(obj.entries.rbegin()->second.where,
            fmt::format("{}: subindex {} is beyond the array's count {}", object_name(index), highest, count));
  }
  out.entries.push_back(build_sub0(index, obj, count));
  for (unsigned sub = 1; sub <= count; ++sub) {
    auto it = obj.entries.find(static_cast<std::uint8_t>(sub));
    const ElementSpec e = layered(obj, kArrayInherited, it == obj.entries.end() ? nullptr : &it->second);
    out.entries.push_back(build_entry(index, static_cast<std::uint8_t>(sub), e, out.type,
                                      array_element_name(static_cast<std::uint8_t>(sub))));
  }
}

void build_record(std::uint16_t index, const ObjectSpec& obj, od::Object& out) {
  out.type = DataType::Record;
  if (const Attr* t = obj.attrs.find("type")) {
    auto it = std::find_if(kStructuredTypes.begin(), kStructuredTypes.end(),
                           [&](const auto& p) { return p.first == t->value; });
    if (it == kStructuredTypes.end()) fail_at(t->where, fmt::format("unknown structured type '{}'", t->value));
    out.type = it->second;
  }
  const std::uint8_t highest = obj.entries.empty() ? 0 : obj.entries.rbegin()->first;
  out.entries.push_back(build_sub0(index, obj, highest));
  for (const auto& [sub, spec] : obj.entries) {
    if (sub == 0) continue;
    const ElementSpec e = layered(obj, kRecordInherited, &spec);
    out.entries.push_back(build_entry(index, sub, e, std::nullopt, ""));
  }
}

}  // namespace

od::Object build_object(std::uint16_t index, const ObjectSpec& obj) {
  od::Object out;
  out.index = index;
  out.name = attr_text(obj, "name");
  if (out.name.empty()) fail_at(obj.where, fmt::format("object {} has no name", object_name(index)));
  out.type_name = attr_text(obj, "typeName");
  out.description = attr_text(obj, "description");
  out.source_line = obj.where.line;
  const std::string code = attr_text(obj, "code", "VAR");
  if (code == "ARRAY") {
    out.code = od::ObjectCode::Array;
    build_array(index, obj, out);
  } else if (code == "RECORD") {
    out.code = od::ObjectCode::Record;
    build_record(index, obj, out);
  } else {
    out.code = od::ObjectCode::Var;
    if (!obj.entries.empty()) {
      fail_at(obj.entries.begin()->second.where,
              fmt::format("{} is a VAR and cannot have Entry elements (use code=\"ARRAY\" or \"RECORD\")",
                          object_name(index)));
    }
    od::Entry e = build_entry(index, 0, obj, std::nullopt, out.name);
    out.type = e.type;
    out.entries.push_back(std::move(e));
  }
  return out;
}

}  // namespace ecat::esi
