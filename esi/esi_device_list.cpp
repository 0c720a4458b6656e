#include "esi/esi_device_list.hpp"

#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <pugixml.hpp>

#include "esi/esi_reader_context.hpp"

namespace ecat::esi {
namespace {

std::string code_text(const std::optional<std::uint32_t>& value, const std::string& text) {
  if (value) return fmt::format("#x{:08X}", *value);
  return text.empty() ? std::string("?") : text;
}

}  // namespace

EsiDeviceEntry device_entry(const pugi::xml_node& device, const EsiContext& ctx) {
  const auto type = device.child("Type");
  EsiDeviceEntry e;
  e.type = type.child_value();
  e.name = esi_name(device);
  e.product_code_text = type.attribute("ProductCode").value();
  e.revision_text = type.attribute("RevisionNo").value();
  e.product_code = parse_esi_number(e.product_code_text);
  e.revision = parse_esi_number(e.revision_text);
  e.line = ctx.line(device);
  return e;
}

std::string format_device_line(const EsiDeviceEntry& e) {
  return fmt::format("{}\t{}\t{}\t{}", e.type, code_text(e.product_code, e.product_code_text),
                     code_text(e.revision, e.revision_text), e.name);
}

std::string describe_device(const EsiDeviceEntry& e) {
  return fmt::format("{} (product code {}, revision {}, line {})", e.type,
                     code_text(e.product_code, e.product_code_text), code_text(e.revision, e.revision_text),
                     e.line);
}

std::string describe_selection(const EsiSelection& s) {
  std::string out;
  if (s.type_name) out += fmt::format(" type '{}'", *s.type_name);
  if (s.product_code) out += fmt::format(" product code #x{:08X}", *s.product_code);
  if (s.revision) out += fmt::format(" revision #x{:08X}", *s.revision);
  return out;
}

bool selection_given(const EsiSelection& s) noexcept {
  return s.product_code.has_value() || s.revision.has_value() || s.type_name.has_value();
}

bool selection_matches(const EsiSelection& s, const EsiDeviceEntry& e) {
  if (s.product_code && e.product_code != s.product_code) return false;
  if (s.revision && e.revision != s.revision) return false;
  if (s.type_name && e.type != *s.type_name) return false;
  return true;
}

Expected<std::vector<EsiDeviceEntry>, LoadError> list_esi_devices(std::string_view xml,
                                                                  std::string_view name) {
  EsiContext ctx(std::string(name), xml, nullptr);
  pugi::xml_document doc;
  auto parsed_root = parse_root(doc, xml, name, "EtherCATInfo", "ESI");
  if (!parsed_root) return ecat::fail(parsed_root.error());
  auto info = *parsed_root;
  auto devices = info.child("Descriptions").child("Devices");
  std::vector<EsiDeviceEntry> out;
  for (auto dev : devices.children("Device")) out.push_back(device_entry(dev, ctx));
  if (out.empty()) return ecat::fail(ctx.error(devices ? devices : info, "the file describes no device"));
  return out;
}

Expected<std::vector<EsiDeviceEntry>, LoadError> list_esi_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return ecat::fail(LoadError{path.string(), 0, "cannot open file"});
  std::ostringstream text;
  text << in.rdbuf();
  return list_esi_devices(text.str(), path.string());
}

}  // namespace ecat::esi
