// Shared state of one ESI import: the file name, the line index for pugixml
// offsets, the warnings list and small typed accessors for ESI values.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <pugixml.hpp>

#include "common/expected.hpp"
#include "esi/device_error.hpp"
#include "esi/esi_device_list.hpp"
#include "esi/esi_reader.hpp"
#include "esi/xml_lines.hpp"
#include "od/device.hpp"

namespace ecat::esi {

class EsiContext {
 public:
  EsiContext(std::string file, std::string_view text, std::vector<EsiWarning>* warnings)
      : file_(std::move(file)), lines_(text), warnings_(warnings) {}

  // The node's position: its line, with the column of its '<' when the line
  // holds other elements too (pugixml's offset is that of the name, one past '<').
  SourcePos line(const pugi::xml_node& n) const {
    const std::ptrdiff_t at = n.offset_debug();
    return lines_.position_of(at > 0 && n.type() == pugi::node_element ? at - 1 : at);
  }
  void warn(const pugi::xml_node& n, std::string message) const {
    if (warnings_) warnings_->push_back({n.name(), line(n), std::move(message)});
  }
  void warn_at(std::string element, SourcePos line, std::string message) const {
    if (warnings_) warnings_->push_back({std::move(element), line, std::move(message)});
  }
  // Warns "element not modelled; ignored".
  void ignored(const pugi::xml_node& n) const { warn(n, "not modelled; ignored"); }
  LoadError error(const pugi::xml_node& n, std::string message) const {
    return LoadError{file_, line(n), std::move(message)};
  }
  const std::string& file() const { return file_; }

 private:
  std::string file_;
  LineIndex lines_;
  std::vector<EsiWarning>* warnings_;
};

// Text of a HexDecValue child or attribute as a number (nullopt if absent/bad).
std::optional<std::int64_t> esi_number(std::string_view text);
// xs:boolean.
bool esi_bool(const pugi::xml_attribute& a, bool fallback = false);
// The Name child in LcId 1033 (English), else the first one.
std::string esi_name(const pugi::xml_node& parent, const char* element = "Name");

// A number that must fit T: nullopt-free; a missing attribute/text gives
// `fallback`, a bad or out-of-range one a warning on `where` and `fallback`.
template <typename T>
T ranged(const EsiContext& ctx, const pugi::xml_node& where, std::string_view what,
         std::string_view text, T fallback) {
  if (text.empty()) return fallback;
  auto v = esi_number(text);
  // "#x0x6041": both hex prefixes, as some ESI generators write them; the
  // number is plain, the spelling is repaired with a warning.
  if (!v && (text.starts_with("#x0x") || text.starts_with("#x0X"))) {
    v = esi_number(std::string("#x").append(text.substr(4)));
    if (v) ctx.warn(where, std::string(what) + " '" + std::string(text) + "' has two hex prefixes; read as #x" +
                               std::string(text.substr(4)));
  }
  if (!v || *v < static_cast<std::int64_t>(std::numeric_limits<T>::min()) ||
      *v > static_cast<std::int64_t>(std::numeric_limits<T>::max())) {
    ctx.warn(where, std::string(what) + " '" + std::string(text) + "' is not a number in range; " +
                        "taken as " + std::to_string(fallback));
    return fallback;
  }
  return static_cast<T>(*v);
}

// The listing entry of one Device element (esi_device_list.cpp).
EsiDeviceEntry device_entry(const pugi::xml_node& device, const EsiContext& ctx);

// Reads one Device element (and the file's Vendor/Groups from `info`).
Expected<void, LoadError> read_esi_device(const pugi::xml_node& info, const pugi::xml_node& device,
                                          const EsiContext& ctx, od::DeviceDescription& out);

// The twin import policy (docs/twins.md): the dictionary objects that repeat
// what the SII says (1018h, 1C00h, 1C12h/1C13h, 16xxh/1Axxh) follow the SII
// where they disagree, PDO entries without an object get one; each repair is
// a warning with its line.
// Device/Slots and the Descriptions/Modules they name (esi_reader_modules.cpp):
// fills d.modular and places each slot's default module (MinInstances
// copies) at its slot indices. `read_pdo` reads one RxPdo/TxPdo element into
// the given description (the device reader's own PDO reading).
using EsiPdoReader = std::function<Expected<void, LoadError>(const pugi::xml_node& pdo, bool rx,
                                                             od::DeviceDescription& into)>;
Expected<void, LoadError> read_esi_modules(const pugi::xml_node& info, const pugi::xml_node& slots,
                                           const EsiContext& ctx, const EsiPdoReader& read_pdo,
                                           od::DeviceDescription& d);

void repair_for_twin(const pugi::xml_node& device, const EsiContext& ctx, od::DeviceDescription& d);

// 16xxh/1Axxh subindices 1..n typed other than UNSIGNED32 (the mapped
// object's type, as Elmo Gold's file has them) become UNSIGNED32, one warning
// per object (twin_mapping_entries.cpp). Run before the mapping defaults are
// compared with the PDOs.
void repair_mapping_entry_types(const EsiContext& ctx, od::DeviceDescription& d);

// Reads Profile/Dictionary into the device (DataTypes resolved, Objects with
// Info and Flags); objects the model cannot hold are skipped with a warning.
void read_esi_dictionary(const pugi::xml_node& dictionary, const EsiContext& ctx,
                         od::Dictionary& out);

// Parses `xml` into `doc` and returns its root element `root`; a parse error
// or another root is a LoadError naming `name` (and the line, for a parse
// error). `what` names the kind of file in the message ("ESI", "ENI").
inline Expected<pugi::xml_node, LoadError> parse_root(pugi::xml_document& doc, std::string_view xml,
                                                      std::string_view name, const char* root,
                                                      std::string_view what) {
  auto parsed = doc.load_buffer(xml.data(), xml.size());
  if (!parsed) {
    LineIndex lines(xml);
    return ecat::fail(LoadError{std::string(name), lines.position_of(parsed.offset),
                                fmt::format("XML parse error: {}", parsed.description())});
  }
  auto node = doc.child(root);
  if (!node) {
    return ecat::fail(LoadError{std::string(name), 0, fmt::format("not an {} file: no {} root element", what, root)});
  }
  return node;
}

}  // namespace ecat::esi
