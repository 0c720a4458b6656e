// What the slave checks about synchronisation before PreOp->SafeOp and
// SafeOp->Op (ETG.1000.6 §6.4.1 / ETG.1020; esm-al-codes.md §3-4), as pure
// functions over what the master configured, so every code is testable.
#pragma once

#include <cstdint>

#include "coe/sync_mode.hpp"
#include "esc/al_status_code.hpp"
#include "od/device.hpp"

namespace ecat::coe {

// The master's configuration at PreOp->SafeOp.
struct SyncSettings {
  bool has_outputs = true;
  bool has_inputs = true;
  SyncMode output_mode = SyncMode::FreeRun;   // 1C32h:01
  SyncMode input_mode = SyncMode::FreeRun;    // 1C33h:01
  std::uint32_t cycle_time = 0;               // 1C32h:02 (0 = not given)
  std::uint8_t dc_activation = 0;             // 0x0981
  std::uint32_t sync0_cycle = 0;              // 0x09A0
  std::uint32_t sync1_cycle = 0;              // 0x09A4
  bool outputs_three_buffer = true;           // SM2 control bits 1:0 = 00
};

// PreOp->SafeOp. In order: mode supported (0x0027 free run, 0x0028 others,
// 0x0029 free run on a 1-buffer SM2), DC registers consistent with the mode
// (0x0030), SYNC0 cycle usable (0x0035 single shot or 1C32h:02 disagreeing,
// 0x0036 outside min/max), SYNC1 (0x0037).
esc::AlStatusCode check_sync_for_safeop(const SyncSettings& s, const od::SyncLimits& limits) noexcept;

// The mode the slave runs in when the master did not write 1C3xh:01: DC
// SYNC0 (or SYNC1) if it activated the SYNC unit, else the device default
// unless that is a DC mode nobody activated (then `sm_mode` - 0x01, or 0x22
// for inputs beside outputs - if SM-synchronous is supported, else free run).
SyncMode derive_sync_mode(bool written, SyncMode current, std::uint8_t dc_activation, const od::SyncLimits& limits,
                          SyncMode sm_mode) noexcept;

}  // namespace ecat::coe
