// SDO-side checks of the drive's own settings (CiA 402-2 §8.4): a write of
// 6060h with a mode 6502h does not list, of 6098h with a homing method the
// drive does not offer, or of an option code 605Ah-605Eh outside the
// personality's set is refused with abort 06090030h (value range exceeded)
// and leaves the stored value unchanged. PDO writes bypass this; the drive
// ignores such values there (and sets the warning bit for 6060h).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "coe/object_hooks.hpp"
#include "coe/object_store.hpp"
#include "ds402/drive_config.hpp"
#include "od/axis_layout.hpp"

namespace ecat::ds402 {

class DriveObjectHooks final : public coe::ObjectHooks {
 public:
  // Keeps a copy of `config`; registers for the objects the store has, at
  // the indices axis `axis` of `layout` uses (axis 1: the profile's).
  // Returns how many indices it now guards. Set-up only.
  std::size_t install(coe::ObjectStore& store, const DriveConfig& config, const od::AxisLayout& layout = {},
                      unsigned axis = 1);

  Expected<void, coe::SdoAbort> on_write(coe::ObjectStore& store, const coe::WriteRequest& request) noexcept override;

 static constexpr std::size_t kGuardedCount = 7;

 private:
  DriveConfig config_;
  std::array<std::uint16_t, kGuardedCount> at_{};  // where each guarded object sits for this axis
};

}  // namespace ecat::ds402
