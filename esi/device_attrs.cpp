#include "esi/device_attrs.hpp"

#include <sstream>

#include <fmt/format.h>

#include "esi/device_failure.hpp"
#include "esi/device_values.hpp"

namespace ecat::esi {

Where where_of(const ElementSpec& e, std::string_view name) {
  const Attr* a = e.attrs.find(name);
  return a ? a->where : e.where;
}

std::string attr_text(const ElementSpec& e, std::string_view name, std::string_view fallback) {
  const Attr* a = e.attrs.find(name);
  return a ? a->value : std::string(fallback);
}

bool attr_bool(const ElementSpec& e, std::string_view name, bool fallback) {
  const Attr* a = e.attrs.find(name);
  if (!a) return fallback;
  auto b = parse_bool(a->value);
  if (!b) fail_at(a->where, fmt::format("{} '{}' is not a boolean (true/false)", name, a->value));
  return *b;
}

std::uint64_t attr_unsigned(const ElementSpec& e, std::string_view name, std::uint64_t max,
                            std::uint64_t fallback) {
  const Attr* a = e.attrs.find(name);
  if (!a) return fallback;
  auto v = parse_unsigned(a->value, max);
  if (!v) fail_at(a->where, fmt::format("{} '{}' is out of range (0..{})", name, a->value, max));
  return *v;
}

std::int64_t attr_signed(const ElementSpec& e, std::string_view name, std::int64_t min,
                         std::int64_t max, std::int64_t fallback) {
  const Attr* a = e.attrs.find(name);
  if (!a) return fallback;
  auto v = parse_signed(a->value, min, max);
  if (!v) fail_at(a->where, fmt::format("{} '{}' is out of range ({}..{})", name, a->value, min, max));
  return *v;
}

std::vector<std::string> attr_list(const ElementSpec& e, std::string_view name) {
  std::vector<std::string> out;
  std::istringstream in(attr_text(e, name));
  for (std::string item; in >> item;) out.push_back(item);
  return out;
}

}  // namespace ecat::esi
