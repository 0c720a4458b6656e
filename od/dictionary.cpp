#include "od/dictionary.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace ecat::od {
namespace {

auto by_index = [](const Object& o, std::uint16_t index) { return o.index < index; };

}  // namespace

Expected<void, std::string> Dictionary::validate(const Object& object) {
  if (object.entries.empty()) {
    return fail(fmt::format("object {:04X}h has no entries", object.index));
  }
  for (std::size_t i = 1; i < object.entries.size(); ++i) {
    if (object.entries[i].subindex <= object.entries[i - 1].subindex) {
      return fail(fmt::format("object {:04X}h: subindex {} is duplicated or out of order",
                              object.index, object.entries[i].subindex));
    }
  }
  if (object.entries.front().subindex != 0) {
    return fail(fmt::format("object {:04X}h has no subindex 0", object.index));
  }
  if (object.code == ObjectCode::Var && object.entries.size() != 1) {
    return fail(fmt::format("object {:04X}h is a VAR but has {} entries", object.index,
                            object.entries.size()));
  }
  return {};
}

Expected<void, std::string> Dictionary::put(Object object) {
  if (auto ok = validate(object); !ok) return ok;
  auto it = std::lower_bound(objects_.begin(), objects_.end(), object.index, by_index);
  if (it != objects_.end() && it->index == object.index) {
    *it = std::move(object);
  } else {
    objects_.insert(it, std::move(object));
  }
  return {};
}

bool Dictionary::erase(std::uint16_t index) {
  auto it = std::lower_bound(objects_.begin(), objects_.end(), index, by_index);
  if (it == objects_.end() || it->index != index) return false;
  objects_.erase(it);
  return true;
}

const Object* Dictionary::find(std::uint16_t index) const noexcept {
  auto it = std::lower_bound(objects_.begin(), objects_.end(), index, by_index);
  return (it != objects_.end() && it->index == index) ? &*it : nullptr;
}

Object* Dictionary::find(std::uint16_t index) noexcept {
  return const_cast<Object*>(static_cast<const Dictionary*>(this)->find(index));
}

const Entry* Dictionary::find(std::uint16_t index, std::uint8_t subindex) const noexcept {
  const Object* o = find(index);
  return o ? o->find(subindex) : nullptr;
}

}  // namespace ecat::od
