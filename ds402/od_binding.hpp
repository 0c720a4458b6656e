// Copies the drive's objects between the CoE object store and the plain
// DriveInputs/DriveOutputs each cycle, and forwards the drive's emergency
// requests to CoE. Every entry is looked up once at set-up; an object the
// device does not have is skipped (its DriveInputs field keeps its default).
// No allocation and no lookup per cycle.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "coe/emergency.hpp"
#include "coe/object_store.hpp"
#include "common/clock.hpp"
#include "ds402/drive_config.hpp"
#include "ds402/faults.hpp"
#include "ds402/objects.hpp"
#include "ds402/od_hooks.hpp"

namespace ecat::ds402 {

class DriveBinding {
 public:
  static constexpr std::size_t kInputCount = 48;
  static constexpr std::size_t kOutputCount = 19;

  // `emergency` may be null (then 1001h is written from DriveOutputs instead).
  DriveBinding(coe::ObjectStore& store, coe::Emergency* emergency = nullptr) noexcept;
  // The store keeps a pointer to the hooks inside: the binding stays put.
  DriveBinding(const DriveBinding&) = delete;
  DriveBinding& operator=(const DriveBinding&) = delete;

  // Writes what the drive offers: 6502h supported modes and 60E3h supported
  // homing methods (as many as the array has room for), and installs the
  // SDO checks of DriveObjectHooks on 6060h, 6098h, 605Ah-605Eh. Set-up only.
  void publish(const DriveConfig& config);

  // Store -> inputs, before Drive::step. `in.sync_lost` is not touched.
  void read(DriveInputs& in) const noexcept;
  // Outputs -> store, after Drive::step, then the emergency requests.
  void write(const DriveOutputs& out, EmcyQueue& emergencies, Nanoseconds now = Nanoseconds{0}) noexcept;

  std::size_t bound_inputs() const noexcept;
  std::size_t bound_outputs() const noexcept;
  // Emergencies CoE could not queue (mailbox closed or full).
  std::uint32_t emergencies_lost() const noexcept { return emergencies_lost_; }

 private:
  coe::ObjectStore& store_;
  coe::Emergency* emergency_;
  std::array<coe::ObjectStore::Slot*, kInputCount> in_{};
  std::array<coe::ObjectStore::Slot*, kOutputCount> out_{};
  // The value bytes of each bound entry whose size equals its field's, read
  // and written in place each cycle; null where the entry needs conversion
  // (another width), which then goes through the store.
  std::array<std::uint8_t*, kInputCount> in_bytes_{};
  std::array<std::uint8_t*, kOutputCount> out_bytes_{};
  coe::ObjectStore::Slot* error_register_ = nullptr;
  DriveObjectHooks hooks_;
  std::uint32_t emergencies_lost_ = 0;
};

}  // namespace ecat::ds402
