// ESI import of a modular device (docs/esi-sii.md "Modular devices";
// ETG.2000 Device/Slots, Descriptions/Modules): the slot rules, the module
// types the slots name (PDOs, dictionary, profile number), and the modules an
// ESI configures by itself - each Slot's default module, MinInstances times -
// placed at their slot indices (object + slot · SlotIndexIncrement, PDO +
// slot · SlotPdoIncrement). A PDO entry marked DependOnSlot whose object the
// module's dictionary lacks gets a process-data object in the module, so that
// it moves with its slot. Anything not modelled is a warning with its line.
#include <algorithm>
#include <map>
#include <set>

#include "esi/esi_reader_context.hpp"

namespace ecat::esi {
namespace {

constexpr std::uint32_t kMaxIndex = 0xFFFF;

std::string hex8(std::uint32_t v) { return fmt::format("#x{:08X}", v); }

// A process-data object for slot-dependent entries the module's dictionary lacks.
void add_entry_objects(const pugi::xml_node& pdo_node, const od::Pdo& p, od::ModuleType& t) {
  std::size_t k = 0;
  for (auto e : pdo_node.children("Entry")) {
    if (k >= p.entries.size()) break;
    const od::PdoEntry& pe = p.entries[k++];
    if (pe.index == 0 || !esi_bool(e.child("Index").attribute("DependOnSlot"))) continue;
    auto it = std::find_if(t.objects.begin(), t.objects.end(), [&](const od::Object& o) { return o.index == pe.index; });
    od::Entry entry;
    entry.subindex = pe.subindex;
    entry.name = pe.name;
    entry.type = pe.type;
    entry.bit_length = pe.bit_length;
    entry.access.bits = p.is_rx() ? static_cast<std::uint16_t>(od::Access::kRw | od::Access::kRxPdoMappable)
                                  : static_cast<std::uint16_t>(od::Access::kRo | od::Access::kTxPdoMappable);
    entry.default_value.assign((pe.bit_length + 7u) / 8u, 0);
    if (it == t.objects.end()) {
      od::Object o;
      o.index = pe.index;
      o.name = pe.name;
      if (pe.subindex == 0) {
        o.type = pe.type;
        o.entries.push_back(entry);
      } else {
        o.code = od::ObjectCode::Record;
        o.type = od::DataType::Record;
        od::Entry count;
        count.name = "Number of entries";
        count.default_value = {pe.subindex};
        o.entries = {count, entry};
      }
      t.objects.push_back(std::move(o));
      continue;
    }
    if (it->code != od::ObjectCode::Record || it->find(pe.subindex)) continue;
    it->entries.push_back(entry);
    std::sort(it->entries.begin() + 1, it->entries.end(),
              [](const od::Entry& a, const od::Entry& b) { return a.subindex < b.subindex; });
    it->entries[0].default_value = {it->max_subindex()};
  }
}

Expected<od::ModuleType, LoadError> read_module(const pugi::xml_node& m, const EsiContext& ctx,
                                                const EsiPdoReader& read_pdo, const od::Dictionary& device) {
  od::ModuleType t;
  auto type = m.child("Type");
  t.ident = ranged<std::uint32_t>(ctx, type, "ModuleIdent", type.attribute("ModuleIdent").value(), 0);
  t.type = type.child_value();
  t.module_class = type.attribute("ModuleClass").value();
  t.name = esi_name(m);
  od::DeviceDescription tmp;
  if (auto profile = m.child("Profile")) {
    t.profile = ranged<std::uint32_t>(ctx, profile, "ProfileNo", profile.child_value("ProfileNo"), 0);
    if (auto dict = profile.child("Dictionary")) read_esi_dictionary(dict, ctx, tmp.dictionary);
  }
  std::vector<std::pair<pugi::xml_node, bool>> pdo_nodes;
  for (auto c : m.children()) {
    const std::string_view n = c.name();
    if (n == "RxPdo" || n == "TxPdo") {
      if (auto ok = read_pdo(c, n == "RxPdo", tmp); !ok) return ecat::fail(ok.error());
      pdo_nodes.emplace_back(c, n == "RxPdo");
    } else if (n != "Type" && n != "Name" && n != "Profile" && c.type() == pugi::node_element) {
      ctx.ignored(c);  // Mailbox/InitCmd, DcOpModeName, images, VendorSpecific
    }
  }
  for (const auto& o : tmp.dictionary.objects()) t.objects.push_back(o);
  std::size_t rx = 0, tx = 0;
  for (const auto& [node, is_rx] : pdo_nodes) {
    od::Pdo& p = is_rx ? tmp.rx_pdos[rx++] : tmp.tx_pdos[tx++];
    for (auto& e : p.entries) {  // entries without a DataType: the object's type
      const od::Entry* oe = tmp.dictionary.find(e.index, e.subindex);
      if (!oe) oe = device.find(e.index, e.subindex);
      if (oe && e.index != 0) e.type = oe->type;
    }
    add_entry_objects(node, p, t);
  }
  std::sort(t.objects.begin(), t.objects.end(), [](const od::Object& a, const od::Object& b) { return a.index < b.index; });
  t.rx_pdos = std::move(tmp.rx_pdos);
  t.tx_pdos = std::move(tmp.tx_pdos);
  return t;
}

std::uint16_t increment(const pugi::xml_node& slots, const char* name, const EsiContext& ctx, std::uint16_t fallback) {
  if (auto a = slots.attribute(name)) return ranged<std::uint16_t>(ctx, slots, name, a.value(), fallback);
  for (auto s : slots.children("Slot")) {
    if (auto a = s.attribute(name)) return ranged<std::uint16_t>(ctx, s, name, a.value(), fallback);
  }
  return fallback;
}

void place(const od::ModularDevice& m, const EsiContext& ctx, const pugi::xml_node& slots, od::DeviceDescription& d) {
  for (std::size_t slot = 0; slot < m.configured.size(); ++slot) {
    const od::ModuleType& t = *m.find(m.configured[slot]);
    for (const od::Object& o : t.objects) {
      const std::uint32_t at = m.object_at(o.index, slot);
      if (at > kMaxIndex || d.dictionary.find(static_cast<std::uint16_t>(at))) {
        ctx.warn(slots, fmt::format("slot {} (module {}): object {:04X}h would be {:X}h, which the device already "
                                    "has or which lies beyond FFFFh; the device's is kept", slot, hex8(t.ident),
                                    o.index, at));
        continue;
      }
      od::Object copy = o;
      copy.index = static_cast<std::uint16_t>(at);
      (void)d.dictionary.put(std::move(copy));
    }
    for (const auto* list : {&t.rx_pdos, &t.tx_pdos}) {
      for (const od::Pdo& p : *list) {
        auto& target = p.is_rx() ? d.rx_pdos : d.tx_pdos;
        const std::uint32_t at = m.pdo_at(p.index, slot);
        const bool taken = std::any_of(target.begin(), target.end(), [&](const od::Pdo& q) { return q.index == at; });
        if (at > kMaxIndex || taken) {
          ctx.warn(slots, fmt::format("slot {} (module {}): PDO {:04X}h would be {:X}h, which the device already "
                                      "has; skipped", slot, hex8(t.ident), p.index, at));
          continue;
        }
        od::Pdo copy = p;
        copy.index = static_cast<std::uint16_t>(at);
        for (auto& x : copy.excludes) {
          const bool own = std::any_of(list->begin(), list->end(), [&](const od::Pdo& q) { return q.index == x; });
          if (own) x = static_cast<std::uint16_t>(m.pdo_at(x, slot));
        }
        for (auto& e : copy.entries) {
          const bool own = std::any_of(t.objects.begin(), t.objects.end(), [&](const od::Object& o) { return o.index == e.index; });
          if (own && e.index != 0) e.index = static_cast<std::uint16_t>(m.object_at(e.index, slot));
        }
        target.push_back(std::move(copy));
      }
    }
  }
  for (auto* list : {&d.rx_pdos, &d.tx_pdos}) {
    std::stable_sort(list->begin(), list->end(), [](const od::Pdo& a, const od::Pdo& b) { return a.index < b.index; });
  }
}

}  // namespace

Expected<void, LoadError> read_esi_modules(const pugi::xml_node& info, const pugi::xml_node& slots,
                                           const EsiContext& ctx, const EsiPdoReader& read_pdo,
                                           od::DeviceDescription& d) {
  od::ModularDevice m;
  m.index_increment = increment(slots, "SlotIndexIncrement", ctx, od::kSlotIndexIncrement);
  m.pdo_increment = increment(slots, "SlotPdoIncrement", ctx, od::kSlotPdoIncrement);
  m.download_ident_list = esi_bool(slots.attribute("DownloadModuleIdentList"));
  std::set<std::uint32_t> wanted;
  for (auto s : slots.children()) {
    const std::string_view n = s.name();
    if (n != "Slot") {
      if (s.type() == pugi::node_element) ctx.ignored(s);  // SlotGroupData, ModulePdoGroup, SlotSelections
      continue;
    }
    od::SlotRule r;
    r.name = esi_name(s);
    r.min_instances = ranged<unsigned>(ctx, s, "MinInstances", s.attribute("MinInstances").value(), 0);
    r.max_instances = ranged<unsigned>(ctx, s, "MaxInstances", s.attribute("MaxInstances").value(), 1);
    for (auto c : s.children()) {
      const std::string_view cn = c.name();
      if (cn == "ModuleIdent") {
        r.idents.push_back(ranged<std::uint32_t>(ctx, c, "ModuleIdent", c.child_value(), 0));
        const std::string_view def = c.attribute("Default").value();
        if (!def.empty() && def != "0" && def != "false") r.default_ident = r.idents.back();
        wanted.insert(r.idents.back());
      } else if (cn == "ModuleClass") {
        ctx.warn(c, "a slot that takes modules by class is not modelled; the slot takes none");
      } else if (cn != "Name" && c.type() == pugi::node_element) {
        ctx.ignored(c);
      }
    }
    for (const char* a : {"SlotGroup", "SlotGroupIndexIncrement", "SlotGroupPdoIncrement"}) {
      if (s.attribute(a)) ctx.warn(s, fmt::format("{} is not modelled; ignored", a));
    }
    m.slots.push_back(std::move(r));
  }
  for (auto mod : info.child("Descriptions").child("Modules").children("Module")) {
    auto ident = esi_number(mod.child("Type").attribute("ModuleIdent").value());
    if (!ident || !wanted.contains(static_cast<std::uint32_t>(*ident)) || m.find(static_cast<std::uint32_t>(*ident))) continue;
    auto t = read_module(mod, ctx, read_pdo, d.dictionary);
    if (!t) return ecat::fail(t.error());
    m.types.push_back(std::move(*t));
  }
  for (od::SlotRule& r : m.slots) {
    std::erase_if(r.idents, [&](std::uint32_t i) {
      if (m.find(i)) return false;
      ctx.warn(slots, fmt::format("Slot '{}' names module {}, which the file does not describe; dropped", r.name, hex8(i)));
      return true;
    });
    if (r.default_ident && !m.find(*r.default_ident)) r.default_ident.reset();
    if (r.min_instances == 0) continue;
    if (!r.default_ident && !r.idents.empty()) {
      ctx.warn(slots, fmt::format("Slot '{}' has no default module; its first module {} is configured", r.name,
                                  hex8(r.idents.front())));
      r.default_ident = r.idents.front();
    }
    if (!r.default_ident) continue;
    // Refused before placing: a slot's MinInstances 65535 made the import
    // place 65535 modules (40 s) only for the twin's loader to refuse it.
    if (m.configured.size() + std::uint64_t{r.min_instances} > od::kMaxModules) {
      return ecat::fail(ctx.error(slots, fmt::format("the slots' default modules number {} or more, more than the {} "
                                                     "that F030h/F050h can list (the twin cannot represent this; the "
                                                     "import refuses it)",
                                                     m.configured.size() + std::uint64_t{r.min_instances},
                                                     od::kMaxModules)));
    }
    for (unsigned k = 0; k < r.min_instances; ++k) m.configured.push_back(*r.default_ident);
  }
  if (m.configured.empty()) {
    ctx.warn(slots, "no module is configured by the slots' defaults; the device is imported without its modules");
    return {};
  }
  place(m, ctx, slots, d);
  d.modular = std::move(m);
  return {};
}

}  // namespace ecat::esi
