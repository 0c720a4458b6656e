#include "esi/esi_writer_dictionary.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "esi/esi_writer_names.hpp"

namespace ecat::esi {
namespace {

// Subindex 0 of an ARRAY/RECORD occupies a 16-bit slot in the complete-access
// image (UNSIGNED8 value + 8 padding bits), as ETG.1000.6 §5.6.2 complete
// access and the masters' ESI parsers expect.
constexpr std::uint32_t kSubindex0SlotBits = 16;
// Objects that ETG.1000.6 makes mandatory for every CoE device.
constexpr std::array<std::uint16_t, 2> kMandatoryObjects = {0x1000, 0x1018};

struct SubItemDef {
  std::optional<std::uint8_t> subidx;
  std::string name;
  std::string type;
  std::uint32_t bit_size = 0;
  std::uint32_t bit_offs = 0;
  od::Access access;
};

struct DataTypeDef {
  std::string base_type;
  std::uint32_t bit_size = 0;
  std::optional<std::uint32_t> array_elements;  // ArrayInfo with LBound 1 (or 0 for BYTE arrays)
  std::uint32_t lbound = 1;
  std::vector<SubItemDef> sub_items;
};

class DataTypes {
 public:
  // Registers the ESI type of an entry (and what it refers to); returns its name.
  std::string add_entry_type(od::DataType t, std::uint16_t bits) {
    std::string name = esi_entry_type_name(t, bits);
    if (t == od::DataType::OctetString && bits > 0) {
      add_entry_type(od::DataType::Byte, 8);
      DataTypeDef def{"BYTE", bits, bits / 8u, 0, {}};
      types_.emplace(name, def);
    } else {
      types_.emplace(name, DataTypeDef{{}, bits, std::nullopt, 1, {}});
    }
    return name;
  }
  bool used(const std::string& name) const { return types_.count(name) != 0; }
  void add(const std::string& name, DataTypeDef def) { types_.emplace(name, std::move(def)); }
  void write(pugi::xml_node parent) const;

 private:
  std::map<std::string, DataTypeDef> types_;  // sorted by name: deterministic output
};

void append_text(pugi::xml_node parent, const char* name, const std::string& text) {
  parent.append_child(name).text().set(text.c_str());
}

void append_flags(pugi::xml_node parent, const od::Access& a, const char* category) {
  auto flags = parent.append_child("Flags");
  const EsiAccess acc = esi_access(a);
  auto access = flags.append_child("Access");
  access.text().set(acc.access.c_str());
  if (!acc.read_restrictions.empty()) {
    access.append_attribute("ReadRestrictions").set_value(acc.read_restrictions.c_str());
  }
  if (!acc.write_restrictions.empty()) {
    access.append_attribute("WriteRestrictions").set_value(acc.write_restrictions.c_str());
  }
  if (category) append_text(flags, "Category", category);
  if (auto m = esi_pdo_mapping(a); !m.empty()) append_text(flags, "PdoMapping", m);
  if (a.bits & od::Access::kBackup) append_text(flags, "Backup", "1");
  if (a.bits & od::Access::kSetting) append_text(flags, "Setting", "1");
}

void DataTypes::write(pugi::xml_node parent) const {
  auto list = parent.append_child("DataTypes");
  for (const auto& [name, def] : types_) {
    auto dt = list.append_child("DataType");
    append_text(dt, "Name", name);
    if (!def.base_type.empty()) append_text(dt, "BaseType", def.base_type);
    append_text(dt, "BitSize", std::to_string(def.bit_size));
    if (def.array_elements) {
      auto info = dt.append_child("ArrayInfo");
      append_text(info, "LBound", std::to_string(def.lbound));
      append_text(info, "Elements", std::to_string(*def.array_elements));
    }
    for (const auto& s : def.sub_items) {
      auto si = dt.append_child("SubItem");
      if (s.subidx) append_text(si, "SubIdx", std::to_string(*s.subidx));
      append_text(si, "Name", s.name);
      append_text(si, "Type", s.type);
      append_text(si, "BitSize", std::to_string(s.bit_size));
      append_text(si, "BitOffs", std::to_string(s.bit_offs));
      append_flags(si, s.access, nullptr);
    }
  }
}

// Names of an object's entries, unique within the object (the ESI keys
// SubItems by Name): a repeated or empty name becomes "SubIndex nnn".
std::vector<std::string> unique_names(const od::Object& o) {
  std::vector<std::string> out;
  std::set<std::string> seen;
  for (const auto& e : o.entries) {
    std::string n = e.name;
    if (n.empty() || seen.count(n)) n = fmt::format("SubIndex {:03}", e.subindex);
    seen.insert(n);
    out.push_back(n);
  }
  return out;
}

// An ARRAY written with ArrayInfo needs elements 1..n of one type and size.
bool regular_array(const od::Object& o) {
  if (o.code != od::ObjectCode::Array || o.entries.size() < 2) return false;
  const auto& first = o.entries[1];
  for (std::size_t i = 1; i < o.entries.size(); ++i) {
    const auto& e = o.entries[i];
    if (e.subindex != i || e.type != first.type || e.bit_length != first.bit_length ||
        !(e.access == first.access)) {
      return false;
    }
  }
  return true;
}

std::string structured_type_name(const od::Object& o, const DataTypes& types) {
  if (!o.type_name.empty() && !types.used(o.type_name) && !types.used(o.type_name + "ARR")) {
    return o.type_name;
  }
  std::string name = fmt::format("DT{:04X}", o.index);
  for (int n = 1; types.used(name); ++n) name = fmt::format("DT{:04X}_{}", o.index, n);
  return name;
}

// Registers the DataType(s) of an ARRAY/RECORD; returns {type name, object bit size}.
std::pair<std::string, std::uint32_t> add_structured(const od::Object& o,
                                                     const std::vector<std::string>& names,
                                                     DataTypes& types) {
  const std::string dt = structured_type_name(o, types);
  DataTypeDef def;
  const auto& sub0 = o.entries.front();
  def.sub_items.push_back({sub0.subindex, names[0], types.add_entry_type(sub0.type, sub0.bit_length),
                           sub0.bit_length, 0, sub0.access});
  std::uint32_t offs = std::max<std::uint32_t>(kSubindex0SlotBits, sub0.bit_length);
  if (regular_array(o)) {
    const auto& e = o.entries[1];
    const auto n = static_cast<std::uint32_t>(o.entries.size() - 1);
    const std::string arr = dt + "ARR";
    types.add(arr, DataTypeDef{types.add_entry_type(e.type, e.bit_length), n * e.bit_length, n, 1, {}});
    def.sub_items.push_back({std::nullopt, "Elements", arr, n * e.bit_length, offs, e.access});
    offs += n * e.bit_length;
  } else {
    for (std::size_t i = 1; i < o.entries.size(); ++i) {
      const auto& e = o.entries[i];
      def.sub_items.push_back({e.subindex, names[i], types.add_entry_type(e.type, e.bit_length),
                               e.bit_length, offs, e.access});
      offs += e.bit_length;
    }
  }
  def.bit_size = offs;
  types.add(dt, def);
  return {dt, offs};
}

void append_values(pugi::xml_node info, const od::Entry& e) {
  if (e.type == od::DataType::VisibleString) {
    if (!e.default_value.empty()) {
      append_text(info, "DefaultString",
                  std::string(e.default_value.begin(), e.default_value.end()));
    }
    return;
  }
  if (e.has_min()) append_text(info, "MinData", hex_binary(e.min_value));
  if (e.has_max()) append_text(info, "MaxData", hex_binary(e.max_value));
  if (!e.default_value.empty()) append_text(info, "DefaultData", hex_binary(e.default_value));
}

bool has_values(const od::Entry& e) {
  return e.has_min() || e.has_max() || !e.default_value.empty();
}

void append_object(pugi::xml_node objects, const od::Object& o, DataTypes& types) {
  auto obj = objects.append_child("Object");
  append_text(obj, "Index", esi_hex(o.index, 4));
  append_text(obj, "Name", o.name);
  if (!o.description.empty()) append_text(obj, "Comment", o.description);
  const bool mandatory = std::find(kMandatoryObjects.begin(), kMandatoryObjects.end(), o.index) !=
                         kMandatoryObjects.end();
  const char* category = mandatory ? "m" : "o";
  if (o.code == od::ObjectCode::Var) {
    const auto& e = o.entries.front();
    append_text(obj, "Type", types.add_entry_type(e.type, e.bit_length));
    append_text(obj, "BitSize", std::to_string(e.bit_length));
    if (has_values(e)) append_values(obj.append_child("Info"), e);
    append_flags(obj, e.access, category);
    return;
  }
  const auto names = unique_names(o);
  auto [type, bits] = add_structured(o, names, types);
  append_text(obj, "Type", type);
  append_text(obj, "BitSize", std::to_string(bits));
  auto info = obj.append_child("Info");
  for (std::size_t i = 0; i < o.entries.size(); ++i) {
    auto si = info.append_child("SubItem");
    append_text(si, "Name", names[i]);
    append_values(si.append_child("Info"), o.entries[i]);
  }
  append_flags(obj, o.entries.front().access, category);
}

}  // namespace

void append_dictionary(pugi::xml_node profile, const od::Dictionary& dictionary) {
  auto dict = profile.append_child("Dictionary");
  DataTypes types;
  // Objects first (into a detached document) so DataTypes is complete; then
  // DataTypes goes before Objects as the schema's sequence requires.
  pugi::xml_document scratch;
  auto objects = scratch.append_child("Objects");
  for (const auto& o : dictionary.objects()) append_object(objects, o, types);
  types.write(dict);
  dict.append_copy(objects);
}

}  // namespace ecat::esi
