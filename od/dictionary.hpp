// The object dictionary: objects sorted by index, found by binary search, with
// the invariants checked on insertion (STYLE lesson 4: no unwritten rules).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "common/expected.hpp"
#include "od/object.hpp"

namespace ecat::od {

class Dictionary {
 public:
  // Adds or replaces (same index) an object. Fails with a message if the
  // object breaks an invariant: entries unsorted or duplicated, a VAR with
  // other than one entry at subindex 0, an ARRAY/RECORD without subindex 0.
  Expected<void, std::string> put(Object object);
  bool erase(std::uint16_t index);

  const Object* find(std::uint16_t index) const noexcept;
  Object* find(std::uint16_t index) noexcept;
  const Entry* find(std::uint16_t index, std::uint8_t subindex) const noexcept;

  std::span<const Object> objects() const noexcept { return objects_; }
  std::size_t size() const noexcept { return objects_.size(); }
  bool empty() const noexcept { return objects_.empty(); }

  // Checks one object on its own; put() calls it.
  static Expected<void, std::string> validate(const Object& object);

 private:
  std::vector<Object> objects_;  // sorted by index, unique
};

}  // namespace ecat::od
