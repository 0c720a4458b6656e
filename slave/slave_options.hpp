// How one virtual slave is set up beyond its device description.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "coe/storage_quota.hpp"
#include "common/clock.hpp"

namespace ecat::slave {

struct SlaveOptions {
  // Where stored parameters (1010h) and FoE files live; empty: nothing is
  // persisted (parameters are still kept for the life of the process).
  std::filesystem::path state_dir;
  // What may be written there, shared by every slave that uses state_dir
  // (ecat-slave makes one for the chain). Null: the slave makes its own with
  // the default limits (64 MiB, 1024 files) over what state_dir holds.
  std::shared_ptr<coe::StorageQuota> state_quota;
  // Name of this slave's files inside state_dir ("slave-1"); chains number them.
  std::string name = "slave";
  // Oscillator error of the DC local clock and its value at time 0.
  double clock_ppm = 0.0;
  std::uint64_t clock_start = 0;
  // Keep a per-cycle motion trace of the drive (for --plot).
  bool motion_trace = false;
};

}  // namespace ecat::slave
