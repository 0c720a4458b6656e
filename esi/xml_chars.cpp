#include "esi/xml_chars.hpp"

#include <cstdint>

#include <pugixml.hpp>

namespace ecat::esi {
namespace {

constexpr char kReplacement = '?';

// Length of the valid UTF-8 sequence at `i` whose code point XML 1.0 allows;
// 0 when the byte starts none.
std::size_t allowed_sequence(std::string_view s, std::size_t i) noexcept {
  const auto b0 = static_cast<std::uint8_t>(s[i]);
  if (b0 < 0x80) return (b0 >= 0x20 || b0 == 0x09 || b0 == 0x0A || b0 == 0x0D) ? 1 : 0;
  std::size_t len = 0;
  std::uint32_t cp = 0;
  if ((b0 & 0xE0) == 0xC0) {
    len = 2;
    cp = b0 & 0x1Fu;
  } else if ((b0 & 0xF0) == 0xE0) {
    len = 3;
    cp = b0 & 0x0Fu;
  } else if ((b0 & 0xF8) == 0xF0) {
    len = 4;
    cp = b0 & 0x07u;
  } else {
    return 0;
  }
  if (i + len > s.size()) return 0;
  for (std::size_t k = 1; k < len; ++k) {
    const auto b = static_cast<std::uint8_t>(s[i + k]);
    if ((b & 0xC0) != 0x80) return 0;
    cp = (cp << 6) | (b & 0x3Fu);
  }
  constexpr std::uint32_t kMinOfLength[] = {0, 0, 0x80, 0x800, 0x10000};
  if (cp < kMinOfLength[len]) return 0;  // overlong
  const bool allowed = (cp >= 0x20 && cp <= 0xD7FF) || (cp >= 0xE000 && cp <= 0xFFFD) ||
                       (cp >= 0x10000 && cp <= 0x10FFFF);
  return allowed ? len : 0;
}

std::string safe_text(std::string_view text, bool normalise_line_ends) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    if (normalise_line_ends && text[i] == '\r') {
      out += '\n';
      i += (i + 1 < text.size() && text[i + 1] == '\n') ? 2 : 1;
      continue;
    }
    const std::size_t n = allowed_sequence(text, i);
    if (n == 0) {
      out += kReplacement;
      ++i;
    } else {
      out.append(text.substr(i, n));
      i += n;
    }
  }
  return out;
}

void make_safe(pugi::xml_node node) {
  for (auto a : node.attributes()) {
    if (find_forbidden_xml_char(a.value())) a.set_value(xml_safe_text(a.value()).c_str());
  }
  for (auto child : node.children()) {
    const auto type = child.type();
    if (type == pugi::node_pcdata || type == pugi::node_cdata || type == pugi::node_comment) {
      const std::string_view v = child.value();
      if (find_forbidden_xml_char(v) || v.find('\r') != std::string_view::npos) {
        child.set_value(safe_text(v, true).c_str());
      }
    } else if (type == pugi::node_element) {
      make_safe(child);
    }
  }
}

}  // namespace

std::optional<std::size_t> find_forbidden_xml_char(std::string_view text) noexcept {
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t n = allowed_sequence(text, i);
    if (n == 0) return i;
    i += n;
  }
  return std::nullopt;
}

std::string xml_safe_text(std::string_view text) { return safe_text(text, false); }

void make_xml_safe(pugi::xml_document& doc) { make_safe(doc); }

}  // namespace ecat::esi
