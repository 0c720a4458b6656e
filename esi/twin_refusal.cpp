#include "esi/twin_refusal.hpp"

#include <string_view>

#include <fmt/format.h>
#include <pugixml.hpp>

#include "esi/device_values.hpp"
#include "esi/xml_lines.hpp"

namespace ecat::esi {
namespace {

constexpr std::uint64_t kMaxIndex = 0xFFFF;

// The first element that starts on `line`.
pugi::xml_node element_on_line(const pugi::xml_node& root, const LineIndex& lines, int line) {
  for (auto n : root.children()) {
    if (n.type() != pugi::node_element) continue;
    if (lines.line_of(n.offset_debug()) == line) return n;
    if (auto inner = element_on_line(n, lines, line)) return inner;
  }
  return {};
}

std::optional<std::uint16_t> index_of(const pugi::xml_node& n) {
  auto v = parse_unsigned(n.attribute("index").value(), kMaxIndex);
  if (!v) return std::nullopt;
  return static_cast<std::uint16_t>(*v);
}

const od::Pdo* pdo_of(const od::DeviceDescription& d, std::uint16_t index) {
  for (const auto* list : {&d.rx_pdos, &d.tx_pdos}) {
    for (const auto& p : *list) {
      if (p.index == index) return &p;
    }
  }
  return nullptr;
}

// The vendor line and element name of the device-file element `n`.
std::pair<SourcePos, std::string> vendor_place(const pugi::xml_node& n, const od::DeviceDescription& d,
                                         const std::vector<SourcePos>& sm_lines) {
  for (auto at = n; at; at = at.parent()) {
    const std::string_view name = at.name();
    if (name == "Sm" && std::string_view(at.parent().name()) == "SyncManagers") {
      const auto sm = parse_unsigned(at.attribute("index").value(), kMaxIndex);
      if (sm && *sm < sm_lines.size()) return {sm_lines[*sm], "Sm"};
    }
    if (name == "RxPdo" || name == "TxPdo") {
      const auto index = index_of(at);
      const od::Pdo* p = index ? pdo_of(d, *index) : nullptr;
      if (p && p->source_line > 0) return {p->source_line, std::string(name)};
    }
    if (name == "Object") {
      const auto index = index_of(at);
      const od::Object* o = index ? d.dictionary.find(*index) : nullptr;
      if (!o) continue;
      if (at != n && std::string_view(n.name()) == "Entry") {
        if (auto sub = parse_unsigned(n.attribute("sub").value(), kMaxIndex)) {
          const od::Entry* e = o->find(static_cast<std::uint8_t>(*sub));
          if (e && e->source_line > 0) return {e->source_line, "SubItem"};
        }
      }
      if (o->source_line > 0) return {o->source_line, "Object"};
    }
  }
  return {0, {}};
}

}  // namespace

LoadError vendor_refusal(const LoadError& refusal, const std::string& device_xml, const od::DeviceDescription& d,
                         const std::string& vendor_file, SourcePos device_line, const std::vector<SourcePos>& sm_lines) {
  SourcePos line = device_line;
  std::string element = "Device";
  pugi::xml_document doc;
  if (refusal.line > 0 && doc.load_buffer(device_xml.data(), device_xml.size())) {
    const LineIndex lines(device_xml);
    if (auto n = element_on_line(doc, lines, refusal.line)) {
      auto [l, e] = vendor_place(n, d, sm_lines);
      if (l > 0) {
        line = l;
        element = e;
      }
    }
  }
  return LoadError{vendor_file, line,
                   fmt::format("{}: {} (the twin cannot represent this; the import refuses it)", element,
                               refusal.message)};
}

}  // namespace ecat::esi
