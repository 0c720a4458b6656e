// Modular devices (docs/device-format.md "Modular devices"; ETG.5001.1
// Modular Device Profile, ETG.2000 Modules/Slots): every configured module is
// given its slot, and a copy of its objects (slot-0 index + slot · indexIncrement)
// and PDOs (slot-0 index + slot · pdoIncrement) joins the device, so the
// dictionary, the PDOs, the SII and the ESI follow the configured modules.
// The MDP objects F000h, F010h, F030h and F050h are derived unless the file
// gives them.
#include <algorithm>
#include <set>

#include <fmt/format.h>

#include "esi/device_attrs.hpp"
#include "esi/device_build.hpp"
#include "esi/device_failure.hpp"
#include "esi/device_parse.hpp"

namespace ecat::esi {
namespace {

constexpr std::uint64_t kMaxIndex = 0xFFFF;
constexpr std::uint64_t kMaxIdent = 0xFFFFFFFF;
constexpr std::uint64_t kMaxModules = od::kMaxModules;

Attr attr(std::string value, const Where& w) { return Attr{std::move(value), w}; }

std::uint32_t ident_of(const ElementSpec& e, std::string_view name) {
  return static_cast<std::uint32_t>(attr_unsigned(e, name, kMaxIdent, 0));
}

std::string hex_index(std::uint64_t index) { return fmt::format("#x{:04X}", index); }
std::string hex_ident(std::uint32_t ident) { return fmt::format("#x{:08X}", ident); }

std::vector<std::uint32_t> ident_list(const ElementSpec& e, std::string_view name) {
  std::vector<std::uint32_t> out;
  for (const auto& item : attr_list(e, name)) {
    ElementSpec one;
    one.attrs.set("x", Attr{item, where_of(e, name)});
    out.push_back(ident_of(one, "x"));
  }
  return out;
}

struct Layout {
  std::uint16_t index_increment = od::kSlotIndexIncrement;
  std::uint16_t pdo_increment = od::kSlotPdoIncrement;
  std::vector<od::SlotRule> rules;
  std::vector<std::uint32_t> configured;  // ident per slot
  std::vector<Where> configured_where;
};

const ModuleSpec* find_module(const ModulesSpec& m, std::uint32_t ident) {
  for (const ModuleSpec& mod : m.modules) {
    if (ident_of(mod.element, "ident") == ident) return &mod;
  }
  return nullptr;
}

std::vector<od::SlotRule> slot_rules(const ModulesSpec& m) {
  std::vector<od::SlotRule> rules;
  unsigned total = 0;
  for (const ElementSpec& s : m.slots) {
    od::SlotRule r;
    r.name = attr_text(s, "name");
    r.min_instances = static_cast<unsigned>(attr_unsigned(s, "min", kMaxModules, 0));
    r.max_instances = static_cast<unsigned>(attr_unsigned(s, "max", kMaxModules, 0));
    if (r.max_instances == 0 || r.min_instances > r.max_instances) {
      fail_at(s.where, fmt::format("Slot '{}': min {} and max {} do not make 1 <= max and min <= max", r.name,
                                   r.min_instances, r.max_instances));
    }
    total += r.max_instances;
    r.idents = ident_list(s, "modules");
    for (std::uint32_t ident : r.idents) {
      if (!find_module(m, ident)) {
        fail_at(where_of(s, "modules"), fmt::format("Slot '{}' names module {}, which no Module declares", r.name,
                                                    hex_ident(ident)));
      }
    }
    if (s.attrs.has("default")) {
      r.default_ident = ident_of(s, "default");
      if (std::find(r.idents.begin(), r.idents.end(), *r.default_ident) == r.idents.end()) {
        fail_at(where_of(s, "default"), fmt::format("Slot '{}': default module {} is not one of its modules",
                                                    r.name, hex_ident(*r.default_ident)));
      }
    }
    rules.push_back(std::move(r));
  }
  if (total > kMaxModules) {
    fail_at(m.element.where, fmt::format("the slots hold up to {} modules, more than the {} that F030h/F050h "
                                         "can list", total, kMaxModules));
  }
  return rules;
}

// The configured modules: the Plug elements, else each slot's default
// module min times (the modules an ESI's Slots give by default).
void configured_modules(const ModulesSpec& m, Layout& l) {
  if (!m.plugs.empty()) {
    for (const ElementSpec& p : m.plugs) {
      const std::uint32_t ident = ident_of(p, "module");
      if (!find_module(m, ident)) {
        fail_at(where_of(p, "module"), fmt::format("Plug of module {}, which no Module declares", hex_ident(ident)));
      }
      l.configured.push_back(ident);
      l.configured_where.push_back(p.where);
    }
    return;
  }
  for (std::size_t k = 0; k < l.rules.size(); ++k) {
    const od::SlotRule& r = l.rules[k];
    if (r.min_instances == 0) continue;
    if (!r.default_ident) {
      fail_at(m.slots[k].where, fmt::format("Slot '{}' needs a default module: no Plug is given and it takes at "
                                            "least {} module(s)", r.name, r.min_instances));
    }
    for (unsigned i = 0; i < r.min_instances; ++i) {
      l.configured.push_back(*r.default_ident);
      l.configured_where.push_back(where_of(m.slots[k], "default"));
    }
  }
}

// ETG.2000 Slots: the configured modules fill the slots in order; each Slot
// element takes between min and max consecutive modules it accepts.
void check_slots(const ModulesSpec& m, const Layout& l) {
  std::size_t pos = 0;
  for (std::size_t k = 0; k < l.rules.size(); ++k) {
    const od::SlotRule& r = l.rules[k];
    unsigned taken = 0;
    while (pos < l.configured.size() && taken < r.max_instances &&
           std::find(r.idents.begin(), r.idents.end(), l.configured[pos]) != r.idents.end()) {
      ++pos;
      ++taken;
    }
    if (taken < r.min_instances) {
      const Where& w = pos < l.configured.size() ? l.configured_where[pos] : m.slots[k].where;
      fail_at(w, fmt::format("Slot '{}' needs at least {} module(s) of {}; {} found{}", r.name, r.min_instances,
                             attr_text(m.slots[k], "modules"), taken,
                             pos < l.configured.size()
                                 ? fmt::format(" (slot {} holds module {})", pos, hex_ident(l.configured[pos]))
                                 : std::string()));
    }
  }
  if (pos < l.configured.size()) {
    fail_at(l.configured_where[pos], fmt::format("module {} in slot {} fits no Slot (the slots before it are full "
                                                 "or do not accept it)", hex_ident(l.configured[pos]), pos));
  }
  if (l.configured.empty()) fail_at(m.element.where, "a modular device needs at least one configured module");
}

Layout layout_of(const ModulesSpec& m) {
  Layout l;
  if (m.element.attrs.has("indexIncrement")) {
    l.index_increment = static_cast<std::uint16_t>(attr_unsigned(m.element, "indexIncrement", kMaxIndex, 0));
  }
  if (m.element.attrs.has("pdoIncrement")) {
    l.pdo_increment = static_cast<std::uint16_t>(attr_unsigned(m.element, "pdoIncrement", kMaxIndex, 0));
  }
  std::set<std::uint32_t> idents;
  for (const ModuleSpec& mod : m.modules) {
    if (!idents.insert(ident_of(mod.element, "ident")).second) {
      fail_at(where_of(mod.element, "ident"), fmt::format("duplicate module ident {}",
                                                          hex_ident(ident_of(mod.element, "ident"))));
    }
  }
  l.rules = slot_rules(m);
  configured_modules(m, l);
  check_slots(m, l);
  return l;
}

std::uint64_t slot_index(std::uint16_t base, std::size_t slot, std::uint16_t increment) {
  return base + std::uint64_t{slot} * increment;
}

std::string describe_slot(std::size_t slot, const ModuleSpec& mod) {
  return fmt::format("slot {} (module {})", slot, hex_ident(ident_of(mod.element, "ident")));
}

void place_objects(DeviceSpec& spec, const ModuleSpec& mod, std::size_t slot, const Layout& l) {
  for (const auto& [base, obj] : mod.objects) {
    const std::uint64_t at = slot_index(base, slot, l.index_increment);
    if (at > kMaxIndex) {
      fail_at(obj.where, fmt::format("{}: object {} would lie beyond FFFFh", describe_slot(slot, mod),
                                     object_name(base)));
    }
    const auto index = static_cast<std::uint16_t>(at);
    if (auto it = spec.objects.find(index); it != spec.objects.end()) {
      fail_at(obj.where, fmt::format("{}: object {} would be {}, which is already defined ({}:{})",
                                     describe_slot(slot, mod), object_name(base), object_name(index),
                                     it->second.where.file, it->second.where.line));
    }
    ObjectSpec copy = obj;
    copy.attrs.set("index", attr(hex_index(index), where_of(obj, "index")));
    spec.objects.emplace(index, std::move(copy));
  }
}

void place_pdos(DeviceSpec& spec, const ModuleSpec& mod, std::size_t slot, const Layout& l) {
  for (const auto& [base, pdo] : mod.pdos) {
    const std::uint64_t at = slot_index(base, slot, l.pdo_increment);
    const auto index = static_cast<std::uint16_t>(std::min<std::uint64_t>(at, kMaxIndex));
    if (auto it = spec.pdos.find(index); it != spec.pdos.end() || at > kMaxIndex) {
      fail_at(pdo.element.where, fmt::format("{}: PDO {} would be {}, which is already defined{}",
                                             describe_slot(slot, mod), object_name(base),
                                             at > kMaxIndex ? std::string("beyond FFFFh") : object_name(index),
                                             it != spec.pdos.end() ? fmt::format(" ({}:{})", it->second.element.where.file,
                                                                                 it->second.element.where.line)
                                                                   : std::string()));
    }
    PdoSpec copy = pdo;
    copy.index = index;
    copy.element.attrs.set("index", attr(hex_index(index), where_of(pdo.element, "index")));
    if (pdo.element.attrs.has("excludes")) {
      std::string list;
      for (const auto& item : attr_list(pdo.element, "excludes")) {
        ElementSpec one;
        one.attrs.set("x", Attr{item, where_of(pdo.element, "excludes")});
        auto x = static_cast<std::uint16_t>(attr_unsigned(one, "x", kMaxIndex, 0));
        if (mod.pdos.contains(x)) x = static_cast<std::uint16_t>(slot_index(x, slot, l.pdo_increment));
        list += (list.empty() ? "" : " ") + hex_index(x);
      }
      copy.element.attrs.set("excludes", attr(list, where_of(pdo.element, "excludes")));
    }
    for (ElementSpec& e : copy.entries) {
      if (!e.attrs.has("index")) continue;
      const auto entry_index = static_cast<std::uint16_t>(attr_unsigned(e, "index", kMaxIndex, 0));
      if (!mod.objects.contains(entry_index)) continue;  // a device object (or a gap): as written
      e.attrs.set("index", attr(hex_index(slot_index(entry_index, slot, l.index_increment)), where_of(e, "index")));
    }
    spec.pdos.emplace(index, std::move(copy));
  }
}

ObjectSpec& ensure(DeviceSpec& spec, std::uint16_t index, const Where& w, bool& created) {
  auto [it, fresh] = spec.objects.try_emplace(index);
  created = fresh;
  if (fresh) it->second.where = w;
  return it->second;
}

void set_entry(ObjectSpec& o, std::uint8_t sub, const Where& w,
               std::initializer_list<std::pair<const char*, std::string>> attrs) {
  ElementSpec& e = o.entries[sub];
  e.where = w;
  for (const auto& [k, v] : attrs) e.attrs.set(k, attr(v, w));
}

// ETG.5001.1 §5: F000h (index distance, maximum number of modules), F010h
// (module profile list), F030h (configured module ident list, the master
// writes it in PreOp), F050h (detected module ident list).
void derive_mdp_objects(DeviceSpec& spec, const ModulesSpec& m, const Layout& l) {
  const Where& w = m.element.where;
  unsigned max_modules = 0;
  for (const od::SlotRule& r : l.rules) max_modules += r.max_instances;
  bool created = false;
  ObjectSpec& f000 = ensure(spec, od::kModularDeviceProfile, w, created);
  if (created) {
    for (const auto& [k, v] : {std::pair{"name", "Modular device profile"}, {"code", "RECORD"}}) f000.attrs.set(k, attr(v, w));
    set_entry(f000, 1, w, {{"name", "Module index distance"}, {"type", "UNSIGNED16"},
                           {"default", hex_index(l.index_increment)}});
    set_entry(f000, 2, w, {{"name", "Maximum number of modules"}, {"type", "UNSIGNED16"},
                           {"default", std::to_string(max_modules)}});
  }
  const std::string n = std::to_string(l.configured.size());
  ObjectSpec& f010 = ensure(spec, od::kModuleProfileList, w, created);
  if (created) {
    for (const auto& [k, v] : {std::pair{"name", "Module profile list"}, {"code", "ARRAY"}, {"type", "UNSIGNED32"}}) {
      f010.attrs.set(k, attr(v, w));
    }
    f010.attrs.set("count", attr(n, w));
    for (std::size_t s = 0; s < l.configured.size(); ++s) {
      const ModuleSpec* mod = find_module(m, l.configured[s]);
      set_entry(f010, static_cast<std::uint8_t>(s + 1), l.configured_where[s],
                {{"default", attr_text(mod->element, "profile", "0")}});
    }
  }
  ObjectSpec& f030 = ensure(spec, od::kConfiguredModuleIdentList, w, created);
  if (created) {
    for (const auto& [k, v] : {std::pair{"name", "Configured module ident list"}, {"code", "ARRAY"},
                               {"type", "UNSIGNED32"}, {"access", "rw"}, {"writeIn", "PreOp"}}) {
      f030.attrs.set(k, attr(v, w));
    }
    f030.attrs.set("count", attr(std::to_string(max_modules), w));
    set_entry(f030, 0, w, {{"access", "rw"}, {"writeIn", "PreOp"}, {"default", "0"},
                           {"max", std::to_string(max_modules)}});
  }
  ObjectSpec& f050 = ensure(spec, od::kDetectedModuleIdentList, w, created);
  if (created) {
    for (const auto& [k, v] : {std::pair{"name", "Detected module ident list"}, {"code", "ARRAY"},
                               {"type", "UNSIGNED32"}}) {
      f050.attrs.set(k, attr(v, w));
    }
    f050.attrs.set("count", attr(n, w));
    for (std::size_t s = 0; s < l.configured.size(); ++s) {
      set_entry(f050, static_cast<std::uint8_t>(s + 1), l.configured_where[s], {{"default", hex_ident(l.configured[s])}});
    }
  }
}

}  // namespace

void derive_modules(DeviceSpec& spec) {
  if (!spec.modules) return;
  const ModulesSpec& m = *spec.modules;
  const Layout l = layout_of(m);
  for (std::size_t slot = 0; slot < l.configured.size(); ++slot) {
    const ModuleSpec& mod = *find_module(m, l.configured[slot]);
    place_objects(spec, mod, slot, l);
    place_pdos(spec, mod, slot, l);
  }
  derive_mdp_objects(spec, m, l);
}

void build_modules(const DeviceSpec& spec, od::DeviceDescription& dev) {
  if (!spec.modules) return;
  const ModulesSpec& m = *spec.modules;
  const Layout l = layout_of(m);
  od::ModularDevice out;
  out.index_increment = l.index_increment;
  out.pdo_increment = l.pdo_increment;
  out.download_ident_list = attr_bool(m.element, "downloadIdentList", true);
  out.slots = l.rules;
  out.configured = l.configured;
  for (const ModuleSpec& mod : m.modules) {
    od::ModuleType t;
    t.ident = ident_of(mod.element, "ident");
    t.type = attr_text(mod.element, "type");
    t.name = attr_text(mod.element, "name", t.type);
    t.module_class = attr_text(mod.element, "class");
    t.profile = static_cast<std::uint32_t>(attr_unsigned(mod.element, "profile", kMaxIdent, 0));
    // The module's PDOs are checked against its slot-0 objects and the
    // device's own objects (a copy of the device with the slot-0 objects in).
    od::DeviceDescription slot0;
    slot0.sync_managers = dev.sync_managers;
    slot0.dictionary = dev.dictionary;
    for (const auto& [index, obj] : mod.objects) {
      od::Object o = build_object(index, obj);
      t.objects.push_back(o);
      if (auto ok = slot0.dictionary.put(std::move(o)); !ok) fail_at(obj.where, ok.error());
    }
    for (const auto& [index, pdo] : mod.pdos) {
      (pdo.rx ? t.rx_pdos : t.tx_pdos).push_back(build_module_pdo(pdo, slot0));
    }
    out.types.push_back(std::move(t));
  }
  dev.modular = std::move(out);
}

}  // namespace ecat::esi
