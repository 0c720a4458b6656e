#include "esi/device_parse.hpp"

#include <set>

#include <fmt/format.h>
#include <pugixml.hpp>

#include "esi/device_failure.hpp"
#include "esi/device_values.hpp"
#include "esi/xml_lines.hpp"

namespace ecat::esi {
namespace {

constexpr std::uint64_t kMaxIndex = 0xFFFF;
constexpr std::uint64_t kMaxSubindex = 0xFF;
// Far above any real device file; keeps sizes within libxml2's int lengths.
constexpr std::size_t kMaxFileBytes = 64u << 20;

// State of one file being read.
class FileReader {
 public:
  FileReader(std::string_view text, const std::string& file, DeviceSpec& spec,
             const IncludeHandler& on_include)
      : lines_(text), file_(file), spec_(spec), on_include_(on_include) {}

  void read_root(const pugi::xml_node& root) {
    const Where w = where(root);
    auto version = parse_unsigned(root.attribute("formatVersion").value(), kMaxIndex);
    if (!version || *version != kFormatVersion) {
      fail_at(w, fmt::format("unsupported formatVersion '{}' (this loader reads {})",
                             root.attribute("formatVersion").value(), kFormatVersion));
    }
    for (const auto& child : root.children()) {
      if (child.type() != pugi::node_element) continue;
      read_part(child);
    }
  }

 private:
  Where where(const pugi::xml_node& node) const {
    return Where{file_, lines_.line_of(node.offset_debug())};
  }

  ElementSpec element(const pugi::xml_node& node) const {
    ElementSpec e;
    e.where = where(node);
    for (const auto& a : node.attributes()) e.attrs.set(a.name(), Attr{a.value(), e.where});
    return e;
  }

  void merge_into(ElementSpec& target, const pugi::xml_node& node) const {
    ElementSpec e = element(node);
    if (target.where.file.empty()) target.where = e.where;
    target.attrs.merge(e.attrs);
  }

  std::vector<ElementSpec> children(const pugi::xml_node& node) const {
    std::vector<ElementSpec> out;
    for (const auto& c : node.children()) {
      if (c.type() == pugi::node_element) out.push_back(element(c));
    }
    return out;
  }

  std::uint64_t number(const pugi::xml_node& node, const char* attr, std::uint64_t max) const {
    const char* text = node.attribute(attr).value();
    auto v = parse_unsigned(text, max);
    if (!v) fail_at(where(node), fmt::format("{} '{}' is out of range (0..{:#x})", attr, text, max));
    return *v;
  }

  void read_part(const pugi::xml_node& node) {
    const std::string_view name = node.name();
    if (name == "Include") {
      on_include_(where(node), node.attribute("href").value());
    } else if (name == "Identity") {
      merge_into(spec_.identity, node);
    } else if (name == "Esc") {
      merge_into(spec_.esc, node);
    } else if (name == "Mailbox") {
      merge_into(spec_.mailbox, node);
    } else if (name == "SyncManagers") {
      spec_.sync_managers = children(node);
      spec_.sync_managers_where = where(node);
    } else if (name == "Fmmus") {
      spec_.fmmus = children(node);
      spec_.fmmus_where = where(node);
    } else if (name == "Dc") {
      merge_into(spec_.dc, node);
      auto modes = children(node);
      if (!modes.empty()) spec_.op_modes = std::move(modes);
    } else if (name == "Objects") {
      read_objects(node);
    } else if (name == "RxPdo" || name == "TxPdo") {
      read_pdo(node, name == "RxPdo");
    } else if (name == "Drive") {
      read_drive(node);
    } else if (name == "Modules") {
      read_modules(node);
    } else {
      fail_at(where(node), fmt::format("unknown element <{}>", name));  // the schema catches it first
    }
  }

  void read_objects(const pugi::xml_node& objects) {
    for (const auto& node : objects.children()) {
      if (node.type() != pugi::node_element) continue;
      const auto index = static_cast<std::uint16_t>(number(node, "index", kMaxIndex));
      if (std::string_view(node.name()) == "Remove") {
        if (spec_.objects.erase(index) == 0) {
          fail_at(where(node), fmt::format("Remove of object {}, which is not defined", object_name(index)));
        }
        defined_here_.erase(index);
        continue;
      }
      read_object(node, index, spec_.objects, defined_here_);
    }
  }

  void read_object(const pugi::xml_node& node, std::uint16_t index, std::map<std::uint16_t, ObjectSpec>& objects,
                   std::map<std::uint16_t, int>& defined) {
    const Where w = where(node);
    if (auto it = defined.find(index); it != defined.end()) {
      fail_at(w, fmt::format("duplicate object {} (first defined at line {})", object_name(index),
                             it->second));
    }
    defined.emplace(index, w.line);
    ObjectSpec& obj = objects[index];
    if (obj.where.file.empty()) obj.where = w;
    obj.attrs.merge(element(node).attrs);
    std::set<std::uint8_t> subs_here;
    for (const auto& e : node.children("Entry")) {
      const auto sub = static_cast<std::uint8_t>(number(e, "sub", kMaxSubindex));
      if (!subs_here.insert(sub).second) {
        fail_at(where(e), fmt::format("duplicate subindex {} in object {}", sub, object_name(index)));
      }
      ElementSpec& entry = obj.entries[sub];
      merge_into(entry, e);
    }
  }

  void read_pdo(const pugi::xml_node& node, bool rx) { read_pdo(node, rx, spec_.pdos, pdos_here_); }

  void read_pdo(const pugi::xml_node& node, bool rx, std::map<std::uint16_t, PdoSpec>& pdos,
                std::map<std::uint16_t, int>& defined) {
    const auto index = static_cast<std::uint16_t>(number(node, "index", kMaxIndex));
    const Where w = where(node);
    if (auto it = defined.find(index); it != defined.end()) {
      fail_at(w, fmt::format("duplicate PDO {} (first defined at line {})", object_name(index),
                             it->second));
    }
    defined.emplace(index, w.line);
    PdoSpec pdo;
    pdo.rx = rx;
    pdo.index = index;
    pdo.element = element(node);
    pdo.entries = children(node);
    pdos[index] = std::move(pdo);
  }

  // <Modules>: module types (each with its own objects and PDOs at slot-0
  // indices), slot rules and the configured modules; replaces an earlier one.
  void read_modules(const pugi::xml_node& node) {
    ModulesSpec m;
    m.element = element(node);
    for (const auto& c : node.children()) {
      if (c.type() != pugi::node_element) continue;
      const std::string_view name = c.name();
      if (name == "Slot") {
        m.slots.push_back(element(c));
      } else if (name == "Plug") {
        m.plugs.push_back(element(c));
      } else if (name == "Module") {
        m.modules.push_back(read_module(c));
      }
    }
    spec_.modules = std::move(m);
  }

  ModuleSpec read_module(const pugi::xml_node& node) {
    ModuleSpec mod;
    mod.element = element(node);
    std::map<std::uint16_t, int> objects_here, pdos_here;
    for (const auto& c : node.children()) {
      if (c.type() != pugi::node_element) continue;
      const std::string_view name = c.name();
      if (name == "Objects") {
        for (const auto& o : c.children("Object")) {
          read_object(o, static_cast<std::uint16_t>(number(o, "index", kMaxIndex)), mod.objects, objects_here);
        }
      } else if (name == "RxPdo" || name == "TxPdo") {
        read_pdo(c, name == "RxPdo", mod.pdos, pdos_here);
      }
    }
    return mod;
  }

  void read_drive(const pugi::xml_node& node) {
    merge_into(spec_.drive, node);
    for (const auto& p : node.children("Plant")) {
      const std::string pname = p.attribute("name").value();
      if (!spec_.plant.contains(pname)) spec_.plant_order.push_back(pname);
      spec_.plant[pname] = Attr{p.attribute("value").value(), where(p)};
    }
    std::vector<ElementSpec> ranges;
    for (const auto& r : node.children("AxisObjects")) ranges.push_back(element(r));
    if (!ranges.empty()) spec_.axis_objects = std::move(ranges);
    for (const auto& x : node.children("AxisIndex")) spec_.axis_indices.push_back(element(x));
  }

  LineIndex lines_;
  const std::string& file_;
  DeviceSpec& spec_;
  const IncludeHandler& on_include_;
  std::map<std::uint16_t, int> defined_here_;  // object index -> line, this file only
  std::map<std::uint16_t, int> pdos_here_;
};

}  // namespace

std::string object_name(std::uint16_t index) { return fmt::format("{:04X}h", index); }

std::string entry_name(std::uint16_t index, std::uint8_t sub) {
  return fmt::format("{:04X}h:{:02X}", index, sub);
}

void parse_device_text(std::string_view text, const std::string& file, const SchemaValidator& schema,
                       DeviceSpec& spec, const IncludeHandler& on_include) {
  if (text.size() > kMaxFileBytes) {
    fail_at(Where{file, 0}, fmt::format("file is larger than {} bytes", kMaxFileBytes));
  }
  pugi::xml_document doc;
  const pugi::xml_parse_result result =
      doc.load_buffer(text.data(), text.size(), pugi::parse_default, pugi::encoding_utf8);
  if (!result) {
    const LineIndex lines(text);
    fail_at(Where{file, lines.line_of(result.offset)},
            fmt::format("XML parse error: {}", result.description()));
  }
  if (auto ok = schema.validate(text, file); !ok) throw LoadFailure{ok.error()};

  FileReader reader(text, file, spec, on_include);
  reader.read_root(doc.document_element());
}

}  // namespace ecat::esi
