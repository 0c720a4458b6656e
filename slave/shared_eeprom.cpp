#include "slave/shared_eeprom.hpp"

#include <algorithm>
#include <functional>
#include <memory>
#include <mutex>
#include <string_view>
#include <unordered_map>

namespace ecat::slave {
namespace {

using Bytes = std::vector<std::uint8_t>;

// Images given out, by a hash of their bytes. Weak: an image lives as long
// as an ESC holds it; expired entries are dropped as they are met.
struct Registry {
  std::mutex mutex;
  std::unordered_multimap<std::size_t, std::weak_ptr<Bytes>> images;
};

Registry& registry() {
  static Registry r;
  return r;
}

std::size_t hash_of(const Bytes& b) {
  return std::hash<std::string_view>{}(std::string_view(reinterpret_cast<const char*>(b.data()), b.size()));
}

}  // namespace

esc::EepromImage shared_eeprom_image(Bytes bytes) {
  Registry& r = registry();
  const std::size_t h = hash_of(bytes);
  std::lock_guard lock(r.mutex);
  auto [first, last] = r.images.equal_range(h);
  for (auto it = first; it != last;) {
    std::shared_ptr<Bytes> held = it->second.lock();
    if (!held) {
      it = r.images.erase(it);
      continue;
    }
    // Registered bytes are never written in place (an EepromImage made from
    // a shared pointer copies before its first write), so equal hash and
    // equal bytes mean the same image.
    if (*held == bytes) return esc::EepromImage(std::move(held));
    ++it;
  }
  auto fresh = std::make_shared<Bytes>(std::move(bytes));
  r.images.emplace(h, fresh);
  return esc::EepromImage(std::move(fresh));
}

}  // namespace ecat::slave
