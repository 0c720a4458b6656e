// AL status codes (register 0x0134), ETG.1000.6 Table 11; shared/spec/esm-al-codes.md §4.
#pragma once

#include <cstdint>
#include <string_view>

namespace ecat::esc {

// EtherCAT state machine states as encoded in AL control/status bits 3:0.
enum class AlState : std::uint8_t { Init = 0x1, PreOp = 0x2, Bootstrap = 0x3, SafeOp = 0x4, Op = 0x8 };

enum class AlStatusCode : std::uint16_t {
  NoError = 0x0000,
  UnspecifiedError = 0x0001,
  NoMemory = 0x0002,
  InvalidDeviceSetup = 0x0003,
  SiiMismatch = 0x0006,
  InvalidRequestedStateChange = 0x0011,
  UnknownRequestedState = 0x0012,
  BootstrapNotSupported = 0x0013,
  NoValidFirmware = 0x0014,
  InvalidMailboxConfigurationBoot = 0x0015,
  InvalidMailboxConfigurationPreOp = 0x0016,
  InvalidSyncManagerConfiguration = 0x0017,
  NoValidInputs = 0x0018,
  NoValidOutputs = 0x0019,
  SynchronizationError = 0x001A,
  SyncManagerWatchdog = 0x001B,
  InvalidSyncManagerTypes = 0x001C,
  InvalidOutputConfiguration = 0x001D,
  InvalidInputConfiguration = 0x001E,
  InvalidWatchdogConfiguration = 0x001F,
  SlaveNeedsColdStart = 0x0020,
  SlaveNeedsInit = 0x0021,
  SlaveNeedsPreOp = 0x0022,
  SlaveNeedsSafeOp = 0x0023,
  InvalidInputMapping = 0x0024,
  InvalidOutputMapping = 0x0025,
  InconsistentSettings = 0x0026,
  FreeRunNotSupported = 0x0027,
  SyncModeNotSupported = 0x0028,
  FreeRunNeeds3BufferMode = 0x0029,
  BackgroundWatchdog = 0x002A,
  NoValidInputsAndOutputs = 0x002B,
  FatalSyncError = 0x002C,
  NoSyncError = 0x002D,
  InvalidDcSyncConfiguration = 0x0030,
  InvalidDcLatchConfiguration = 0x0031,
  PllError = 0x0032,
  DcSyncIoError = 0x0033,
  DcSyncTimeoutError = 0x0034,
  DcInvalidSyncCycleTime = 0x0035,
  DcSync0CycleTime = 0x0036,
  DcSync1CycleTime = 0x0037,
  MailboxAoe = 0x0041,
  MailboxEoe = 0x0042,
  MailboxCoe = 0x0043,
  MailboxFoe = 0x0044,
  MailboxSoe = 0x0045,
  MailboxVoe = 0x004F,
  EepromNoAccess = 0x0050,
  EepromError = 0x0051,
  SlaveRestartedLocally = 0x0060,
  DeviceIdentificationValueUpdated = 0x0061,
  // ETG.1000.6 Table 11 / ETG.5001.1: the configured module ident list (F030h)
  // the master wrote does not match the detected one (F050h); docs/esi-sii.md.
  DetectedModuleIdentListMismatch = 0x0070,
};

// Text as ETG.1000.6 names the code ("Invalid requested state change").
std::string_view describe(AlStatusCode code) noexcept;
std::string_view describe(AlState state) noexcept;

}  // namespace ecat::esc
