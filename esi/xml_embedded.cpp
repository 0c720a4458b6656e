#include "esi/xml_embedded.hpp"

namespace ecat::esi {

std::optional<std::string_view> find_embedded(std::string_view name) noexcept {
  for (const auto& f : embedded_files()) {
    if (f.name == name) return f.content;
  }
  return std::nullopt;
}

}  // namespace ecat::esi
