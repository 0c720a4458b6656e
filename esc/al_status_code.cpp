// Texts for AL status codes and states; names as ETG.1000.6 Table 11 gives
// them (shared/spec/esm-al-codes.md §4).
#include "esc/al_status_code.hpp"

namespace ecat::esc {

std::string_view describe(AlStatusCode code) noexcept {
  switch (code) {
    case AlStatusCode::NoError: return "No error";
    case AlStatusCode::UnspecifiedError: return "Unspecified error";
    case AlStatusCode::NoMemory: return "No memory";
    case AlStatusCode::InvalidDeviceSetup: return "Invalid device setup";
    case AlStatusCode::SiiMismatch: return "SII/EEPROM information does not match firmware";
    case AlStatusCode::InvalidRequestedStateChange: return "Invalid requested state change";
    case AlStatusCode::UnknownRequestedState: return "Unknown requested state";
    case AlStatusCode::BootstrapNotSupported: return "Bootstrap not supported";
    case AlStatusCode::NoValidFirmware: return "No valid firmware";
    case AlStatusCode::InvalidMailboxConfigurationBoot: return "Invalid mailbox configuration (Bootstrap)";
    case AlStatusCode::InvalidMailboxConfigurationPreOp: return "Invalid mailbox configuration (PreOp)";
    case AlStatusCode::InvalidSyncManagerConfiguration: return "Invalid sync manager configuration";
    case AlStatusCode::NoValidInputs: return "No valid inputs available";
    case AlStatusCode::NoValidOutputs: return "No valid outputs";
    case AlStatusCode::SynchronizationError: return "Synchronization error";
    case AlStatusCode::SyncManagerWatchdog: return "Sync manager watchdog";
    case AlStatusCode::InvalidSyncManagerTypes: return "Invalid Sync Manager types";
    case AlStatusCode::InvalidOutputConfiguration: return "Invalid output configuration";
    case AlStatusCode::InvalidInputConfiguration: return "Invalid input configuration";
    case AlStatusCode::InvalidWatchdogConfiguration: return "Invalid watchdog configuration";
    case AlStatusCode::SlaveNeedsColdStart: return "Slave needs cold start";
    case AlStatusCode::SlaveNeedsInit: return "Slave needs INIT";
    case AlStatusCode::SlaveNeedsPreOp: return "Slave needs PREOP";
    case AlStatusCode::SlaveNeedsSafeOp: return "Slave needs SAFEOP";
    case AlStatusCode::InvalidInputMapping: return "Invalid input mapping";
    case AlStatusCode::InvalidOutputMapping: return "Invalid output mapping";
    case AlStatusCode::InconsistentSettings: return "Inconsistent settings";
    case AlStatusCode::FreeRunNotSupported: return "FreeRun not supported";
    case AlStatusCode::SyncModeNotSupported: return "SyncMode not supported";
    case AlStatusCode::FreeRunNeeds3BufferMode: return "FreeRun needs 3-buffer mode";
    case AlStatusCode::BackgroundWatchdog: return "Background watchdog";
    case AlStatusCode::NoValidInputsAndOutputs: return "No valid inputs and outputs";
    case AlStatusCode::FatalSyncError: return "Fatal sync error";
    case AlStatusCode::NoSyncError: return "No sync error";
    case AlStatusCode::InvalidDcSyncConfiguration: return "Invalid DC SYNC configuration";
    case AlStatusCode::InvalidDcLatchConfiguration: return "Invalid DC latch configuration";
    case AlStatusCode::PllError: return "PLL error";
    case AlStatusCode::DcSyncIoError: return "DC sync IO error";
    case AlStatusCode::DcSyncTimeoutError: return "DC sync timeout error";
    case AlStatusCode::DcInvalidSyncCycleTime: return "DC invalid sync cycle time";
    case AlStatusCode::DcSync0CycleTime: return "DC SYNC0 cycle time";
    case AlStatusCode::DcSync1CycleTime: return "DC SYNC1 cycle time";
    case AlStatusCode::MailboxAoe: return "MBX_AOE";
    case AlStatusCode::MailboxEoe: return "MBX_EOE";
    case AlStatusCode::MailboxCoe: return "MBX_COE";
    case AlStatusCode::MailboxFoe: return "MBX_FOE";
    case AlStatusCode::MailboxSoe: return "MBX_SOE";
    case AlStatusCode::MailboxVoe: return "MBX_VOE";
    case AlStatusCode::EepromNoAccess: return "EEPROM no access";
    case AlStatusCode::EepromError: return "EEPROM error";
    case AlStatusCode::SlaveRestartedLocally: return "Slave restarted locally";
    case AlStatusCode::DeviceIdentificationValueUpdated: return "Device identification value updated";
    case AlStatusCode::DetectedModuleIdentListMismatch: return "Detected module ident list does not match";
  }
  const auto raw = static_cast<std::uint16_t>(code);
  // ETG.1000.6 Table 11: 0x8000..0xFFFF vendor specific, the rest reserved.
  constexpr std::uint16_t kFirstVendorCode = 0x8000;
  return raw >= kFirstVendorCode ? "Vendor specific error" : "Reserved AL status code";
}

std::string_view describe(AlState state) noexcept {
  switch (state) {
    case AlState::Init: return "INIT";
    case AlState::PreOp: return "PREOP";
    case AlState::Bootstrap: return "BOOT";
    case AlState::SafeOp: return "SAFEOP";
    case AlState::Op: return "OP";
  }
  return "UNKNOWN";
}

}  // namespace ecat::esc
