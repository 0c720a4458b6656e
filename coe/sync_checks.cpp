// Synchronisation checks; rules in sync_checks.hpp, choices in docs/dc.md.
#include "coe/sync_checks.hpp"

#include "esc/dc/dc_registers.hpp"

namespace ecat::coe {
namespace {

using esc::AlStatusCode;

constexpr std::uint8_t kSync0Active = esc::dcreg::kActivateSyncUnit | esc::dcreg::kActivateSync0;
constexpr std::uint8_t kSync1Active = esc::dcreg::kActivateSyncUnit | esc::dcreg::kActivateSync1;

AlStatusCode check_mode(SyncMode m, bool inputs, const SyncSettings& s, const od::SyncLimits& limits) noexcept {
  switch (m) {
    case SyncMode::FreeRun:
      if (!limits.free_run) return AlStatusCode::FreeRunNotSupported;
      if (!inputs && !s.outputs_three_buffer) return AlStatusCode::FreeRunNeeds3BufferMode;
      return AlStatusCode::NoError;
    case SyncMode::SmSynchronous:
      return limits.sm_synchronous ? AlStatusCode::NoError : AlStatusCode::SyncModeNotSupported;
    case SyncMode::SmSynchronousSm2:
      return inputs && s.has_outputs && limits.sm_synchronous ? AlStatusCode::NoError
                                                              : AlStatusCode::SyncModeNotSupported;
    case SyncMode::DcSync0:
      return limits.dc_sync0 ? AlStatusCode::NoError : AlStatusCode::SyncModeNotSupported;
    case SyncMode::DcSync1:
      return limits.dc_sync1 ? AlStatusCode::NoError : AlStatusCode::SyncModeNotSupported;
  }
  return AlStatusCode::SyncModeNotSupported;
}

}  // namespace

bool is_dc(SyncMode m) noexcept { return m == SyncMode::DcSync0 || m == SyncMode::DcSync1; }

bool is_defined_sync_mode(std::uint16_t value, bool inputs) noexcept {
  switch (static_cast<SyncMode>(value)) {
    case SyncMode::FreeRun:
    case SyncMode::SmSynchronous:
    case SyncMode::DcSync0:
    case SyncMode::DcSync1: return true;
    case SyncMode::SmSynchronousSm2: return inputs;
  }
  return false;
}

AlStatusCode check_sync_for_safeop(const SyncSettings& s, const od::SyncLimits& limits) noexcept {
  if (s.has_outputs) {
    if (const AlStatusCode c = check_mode(s.output_mode, false, s, limits); c != AlStatusCode::NoError) return c;
  }
  if (s.has_inputs) {
    if (const AlStatusCode c = check_mode(s.input_mode, true, s, limits); c != AlStatusCode::NoError) return c;
  }
  const bool dc = (s.has_outputs && is_dc(s.output_mode)) || (s.has_inputs && is_dc(s.input_mode));
  const bool sync1 = (s.has_outputs && s.output_mode == SyncMode::DcSync1) ||
                     (s.has_inputs && s.input_mode == SyncMode::DcSync1);
  const bool unit_active = (s.dc_activation & esc::dcreg::kActivateSyncUnit) != 0;
  if (!dc) {
    // A SYNC unit running for a slave that will not use it (SOES: 0x0030).
    const bool generating = (s.dc_activation & (esc::dcreg::kActivateSync0 | esc::dcreg::kActivateSync1)) != 0;
    return unit_active && generating ? AlStatusCode::InvalidDcSyncConfiguration : AlStatusCode::NoError;
  }
  if ((s.dc_activation & kSync0Active) != kSync0Active) return AlStatusCode::InvalidDcSyncConfiguration;
  if (sync1 && (s.dc_activation & kSync1Active) != kSync1Active) return AlStatusCode::InvalidDcSyncConfiguration;
  if (s.sync0_cycle == 0) return AlStatusCode::DcInvalidSyncCycleTime;  // single shot is no cycle
  if (s.sync0_cycle < limits.min_cycle_time_ns ||
      (limits.max_cycle_time_ns != 0 && s.sync0_cycle > limits.max_cycle_time_ns)) {
    return AlStatusCode::DcSync0CycleTime;
  }
  if (!sync1 && s.cycle_time != 0 && s.cycle_time != s.sync0_cycle) return AlStatusCode::DcInvalidSyncCycleTime;
  if (sync1 && s.sync1_cycle >= s.sync0_cycle && s.sync1_cycle % s.sync0_cycle != 0) {
    return AlStatusCode::DcSync1CycleTime;  // neither a shift nor a multiple of SYNC0
  }
  return AlStatusCode::NoError;
}

SyncMode derive_sync_mode(bool written, SyncMode current, std::uint8_t dc_activation, const od::SyncLimits& limits,
                          SyncMode sm_mode) noexcept {
  if (written) return current;
  if ((dc_activation & kSync0Active) == kSync0Active) return SyncMode::DcSync0;
  if (!is_dc(current)) return current;
  return limits.sm_synchronous ? sm_mode : SyncMode::FreeRun;
}

}  // namespace ecat::coe
