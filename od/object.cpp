#include "od/object.hpp"

#include <algorithm>

namespace ecat::od {

const Entry* Object::find(std::uint8_t subindex) const noexcept {
  auto it = std::lower_bound(entries.begin(), entries.end(), subindex,
                             [](const Entry& e, std::uint8_t s) { return e.subindex < s; });
  return (it != entries.end() && it->subindex == subindex) ? &*it : nullptr;
}

Entry* Object::find(std::uint8_t subindex) noexcept {
  return const_cast<Entry*>(static_cast<const Object*>(this)->find(subindex));
}

std::uint8_t Object::max_subindex() const noexcept {
  return entries.empty() ? 0 : entries.back().subindex;
}

}  // namespace ecat::od
