// A modular device (ETG.5001.1 Modular Device Profile, ETG.2000 <Modules>/<Slots>):
// the module types a device accepts, the slot rules that say which module may
// sit where, and the modules configured (plugged) in it. The device's
// dictionary and PDOs already hold the configured modules' objects and PDOs at
// their slot indices; this keeps what the ESI writer needs to describe the
// module types themselves (at the slot-0 indices, ETG.2000 DependOnSlot).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "od/object.hpp"

namespace ecat::od {

struct Pdo;

// ETG.5001.1 §4: objects of module n (0-based slot) lie at the slot-0 index
// + n·10h in the 6000h/7000h/8000h/9000h areas; PDOs at + n (the usual choice).
inline constexpr std::uint16_t kSlotIndexIncrement = 0x0010;
inline constexpr std::uint16_t kSlotPdoIncrement = 0x0001;

// ETG.5001.1 MDP objects.
inline constexpr std::uint16_t kModularDeviceProfile = 0xF000;      // RECORD: index distance, max modules
inline constexpr std::uint16_t kModuleProfileList = 0xF010;         // ARRAY UDINT: profile of each module
inline constexpr std::uint16_t kConfiguredModuleIdentList = 0xF030;  // ARRAY UDINT, written by the master in PreOp
inline constexpr std::uint16_t kDetectedModuleIdentList = 0xF050;    // ARRAY UDINT, the modules present
// F030h/F050h/F010h are ARRAYs with subindices 1..254 (ETG.5001.1 §5): a
// modular device holds at most this many modules.
inline constexpr unsigned kMaxModules = 254;

struct ModuleType {
  std::uint32_t ident = 0;  // ETG.2000 Module/Type@ModuleIdent; F030h/F050h entries
  std::string type;         // Module/Type text (order code)
  std::string name;         // Module/Name
  std::string module_class; // Module/Type@ModuleClass (empty: none)
  std::uint32_t profile = 0;  // F010h entry (module profile number)
  std::vector<Object> objects;  // at the slot-0 indices
  // At the slot-0 indices; entries that map the module's own objects name them
  // at their slot-0 indices. (Pdo is complete where a ModuleType is used:
  // od/device.hpp; a vector of an incomplete type may be declared, C++17.)
  std::vector<Pdo> rx_pdos, tx_pdos;
};

// One ETG.2000 <Slot>: MinInstances..MaxInstances consecutive slots that
// accept the listed modules.
struct SlotRule {
  std::string name;
  unsigned min_instances = 1;
  unsigned max_instances = 1;
  std::vector<std::uint32_t> idents;        // modules allowed
  std::optional<std::uint32_t> default_ident;  // ModuleIdent@Default
};

struct ModularDevice {
  std::uint16_t index_increment = kSlotIndexIncrement;  // Slots@SlotIndexIncrement
  std::uint16_t pdo_increment = kSlotPdoIncrement;      // Slots@SlotPdoIncrement
  bool download_ident_list = true;                      // Slots@DownloadModuleIdentList
  std::vector<ModuleType> types;
  std::vector<SlotRule> slots;
  std::vector<std::uint32_t> configured;  // module ident in slot 0, 1, ...

  unsigned max_modules() const noexcept {
    unsigned n = 0;
    for (const SlotRule& s : slots) n += s.max_instances;
    return n;
  }
  const ModuleType* find(std::uint32_t ident) const noexcept {
    for (const ModuleType& t : types) {
      if (t.ident == ident) return &t;
    }
    return nullptr;
  }
  // Index of a module's slot-0 object (or PDO) `base` in slot `slot`.
  std::uint32_t object_at(std::uint16_t base, std::size_t slot) const noexcept {
    return base + static_cast<std::uint32_t>(slot) * index_increment;
  }
  std::uint32_t pdo_at(std::uint16_t base, std::size_t slot) const noexcept {
    return base + static_cast<std::uint32_t>(slot) * pdo_increment;
  }
  // Whether object `index` of the device is a configured module's object
  // (the ESI and device XML writers describe those in the module types).
  bool placed_object(std::uint16_t index) const noexcept {
    for (std::size_t slot = 0; slot < configured.size(); ++slot) {
      if (const ModuleType* t = find(configured[slot])) {
        for (const Object& o : t->objects) {
          if (object_at(o.index, slot) == index) return true;
        }
      }
    }
    return false;
  }
  bool placed_pdo(std::uint16_t index) const noexcept;  // od/device.hpp (needs Pdo)
};

}  // namespace ecat::od
