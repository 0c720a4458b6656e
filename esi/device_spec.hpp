// The device file as read, before it is turned into od::DeviceDescription:
// every element keeps its attributes as text together with where they were
// written, so that includes can override single attributes and every later
// check can still name file:line. Merging rules: docs/device-format.md.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ecat::esi {

struct Where {
  std::string file;
  int line = 0;
};

struct Attr {
  std::string value;
  Where where;
};

// Attribute name -> value; a later file's attribute replaces an earlier one.
class AttrMap {
 public:
  void set(std::string name, Attr attr) { attrs_[std::move(name)] = std::move(attr); }
  void merge(const AttrMap& later) {
    for (const auto& [k, v] : later.attrs_) attrs_[k] = v;
  }
  const Attr* find(std::string_view name) const {
    auto it = attrs_.find(name);
    return it == attrs_.end() ? nullptr : &it->second;
  }
  bool has(std::string_view name) const { return find(name) != nullptr; }

 private:
  std::map<std::string, Attr, std::less<>> attrs_;
};

// An element with its attributes: Sm, Fmmu, OpMode, PDO entries, ...
struct ElementSpec {
  Where where;
  AttrMap attrs;
};

// An Object element; `where` is its first definition.
struct ObjectSpec : ElementSpec {
  std::map<std::uint8_t, ElementSpec> entries;  // by subindex
};

struct PdoSpec {
  bool rx = true;
  std::uint16_t index = 0;
  ElementSpec element;
  std::vector<ElementSpec> entries;
};

// <Modules><Module>: one module type with its objects and PDOs at slot-0 indices.
struct ModuleSpec {
  ElementSpec element;
  std::map<std::uint16_t, ObjectSpec> objects;
  std::map<std::uint16_t, PdoSpec> pdos;
};

// <Modules>: a later one replaces the whole earlier one.
struct ModulesSpec {
  ElementSpec element;
  std::vector<ModuleSpec> modules;
  std::vector<ElementSpec> slots;
  std::vector<ElementSpec> plugs;
};

struct DeviceSpec {
  ElementSpec identity, esc, mailbox, dc, drive;
  std::optional<std::vector<ElementSpec>> sync_managers;
  std::optional<std::vector<ElementSpec>> fmmus;
  Where sync_managers_where, fmmus_where;
  std::vector<ElementSpec> op_modes;
  std::map<std::uint16_t, ObjectSpec> objects;
  std::map<std::uint16_t, PdoSpec> pdos;  // Rx and Tx share one index space
  std::map<std::string, Attr> plant;       // by name
  std::vector<std::string> plant_order;    // names in first-definition order
  // <Drive><AxisObjects>: a later Drive with any replaces the list.
  std::optional<std::vector<ElementSpec>> axis_objects;
  // <Drive><AxisIndex>, by (axis text, index text) as written; later ones replace.
  std::vector<ElementSpec> axis_indices;
  std::optional<ModulesSpec> modules;
};

}  // namespace ecat::esi
