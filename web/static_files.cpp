#include "web/static_files.hpp"

#include <array>
#include <cstdlib>
#include <filesystem>
#include <utility>

namespace ecat::web {
namespace {

bool plain_name(std::string_view s) {
  if (s.empty() || s.front() == '.') return false;
  for (const char c : s) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
                    c == '_' || c == '-';
    if (!ok) return false;
  }
  return true;
}

}  // namespace

std::optional<std::string> resolve_static(std::string_view root, std::string_view path) {
  if (path.empty() || path.front() != '/') return std::nullopt;
  if (path == "/") path = "/index.html";
  std::string out(root);
  std::size_t start = 1;
  while (start <= path.size()) {
    const std::size_t slash = std::min(path.find('/', start), path.size());
    const std::string_view segment = path.substr(start, slash - start);
    if (!plain_name(segment)) return std::nullopt;
    out.append("/").append(segment);
    start = slash + 1;
  }
  return out;
}

std::string_view content_type(std::string_view file) {
  static constexpr std::array<std::pair<std::string_view, std::string_view>, 7> kTypes{{
      {".html", "text/html; charset=utf-8"},
      {".css", "text/css; charset=utf-8"},
      {".js", "text/javascript; charset=utf-8"},
      {".json", "application/json"},
      {".svg", "image/svg+xml"},
      {".png", "image/png"},
      {".ico", "image/x-icon"},
  }};
  for (const auto& [ext, type] : kTypes) {
    if (file.size() >= ext.size() && file.substr(file.size() - ext.size()) == ext) return type;
  }
  return "application/octet-stream";
}

std::string find_www_dir(std::string_view option, std::string_view program_dir) {
  if (!option.empty()) return std::string(option);
  if (const char* env = std::getenv("ECAT_WWW_DIR"); env != nullptr && *env != '\0') return env;
  return std::string(program_dir) + "/../share/ecatslave/www";
}

}  // namespace ecat::web
