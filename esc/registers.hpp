// ESC register addresses (Beckhoff ESC datasheet Section II, ETG.1000.4 §6;
// shared/spec/esc-registers.md §3). Named once here; every layer that touches
// the ESC through datagrams or the PDI uses these names.
#pragma once

#include <cstdint>

namespace ecat::esc::reg {

inline constexpr std::uint16_t kType = 0x0000;
inline constexpr std::uint16_t kRevision = 0x0001;
inline constexpr std::uint16_t kBuild = 0x0002;
inline constexpr std::uint16_t kFmmusSupported = 0x0004;
inline constexpr std::uint16_t kSyncManagersSupported = 0x0005;
inline constexpr std::uint16_t kRamSize = 0x0006;
inline constexpr std::uint16_t kPortDescriptor = 0x0007;
inline constexpr std::uint16_t kFeatures = 0x0008;
inline constexpr std::uint16_t kConfiguredStationAddress = 0x0010;
inline constexpr std::uint16_t kConfiguredStationAlias = 0x0012;
inline constexpr std::uint16_t kRegisterWriteEnable = 0x0020;
inline constexpr std::uint16_t kRegisterWriteProtection = 0x0021;
inline constexpr std::uint16_t kEscWriteEnable = 0x0030;
inline constexpr std::uint16_t kEscWriteProtection = 0x0031;
inline constexpr std::uint16_t kEscResetEcat = 0x0040;
inline constexpr std::uint16_t kEscResetPdi = 0x0041;
inline constexpr std::uint16_t kDlControl = 0x0100;
inline constexpr std::uint16_t kPhysicalRwOffset = 0x0108;
inline constexpr std::uint16_t kDlStatus = 0x0110;
inline constexpr std::uint16_t kAlControl = 0x0120;
inline constexpr std::uint16_t kAlStatus = 0x0130;
inline constexpr std::uint16_t kAlStatusCode = 0x0134;
inline constexpr std::uint16_t kRunLedOverride = 0x0138;
inline constexpr std::uint16_t kErrLedOverride = 0x0139;
inline constexpr std::uint16_t kPdiControl = 0x0140;
inline constexpr std::uint16_t kEscConfiguration = 0x0141;
inline constexpr std::uint16_t kPdiInformation = 0x014E;
inline constexpr std::uint16_t kPdiConfiguration = 0x0150;
inline constexpr std::uint16_t kSyncLatchPdiConfiguration = 0x0151;
inline constexpr std::uint16_t kExtendedPdiConfiguration = 0x0152;
inline constexpr std::uint16_t kEcatEventMask = 0x0200;
inline constexpr std::uint16_t kAlEventMask = 0x0204;
inline constexpr std::uint16_t kEcatEventRequest = 0x0210;
inline constexpr std::uint16_t kAlEventRequest = 0x0220;
inline constexpr std::uint16_t kRxErrorCounter = 0x0300;  // 2 bytes per port
inline constexpr std::uint16_t kForwardedRxErrorCounter = 0x0308;
inline constexpr std::uint16_t kProcessingUnitErrorCounter = 0x030C;
inline constexpr std::uint16_t kPdiErrorCounter = 0x030D;
inline constexpr std::uint16_t kPdiErrorCode = 0x030E;
inline constexpr std::uint16_t kLostLinkCounter = 0x0310;
inline constexpr std::uint16_t kWatchdogDivider = 0x0400;
inline constexpr std::uint16_t kWatchdogTimePdi = 0x0410;
inline constexpr std::uint16_t kWatchdogTimeProcessData = 0x0420;
inline constexpr std::uint16_t kWatchdogStatusProcessData = 0x0440;
inline constexpr std::uint16_t kWatchdogCounterProcessData = 0x0442;
inline constexpr std::uint16_t kWatchdogCounterPdi = 0x0443;
inline constexpr std::uint16_t kEepromConfiguration = 0x0500;
inline constexpr std::uint16_t kEepromPdiAccessState = 0x0501;
inline constexpr std::uint16_t kEepromControlStatus = 0x0502;
inline constexpr std::uint16_t kEepromAddress = 0x0504;
inline constexpr std::uint16_t kEepromData = 0x0508;
inline constexpr std::uint16_t kMiiManagementControlStatus = 0x0510;
inline constexpr std::uint16_t kFmmuBase = 0x0600;
inline constexpr std::uint16_t kFmmuStride = 16;
inline constexpr std::uint16_t kSyncManagerBase = 0x0800;
inline constexpr std::uint16_t kSyncManagerStride = 8;
inline constexpr std::uint16_t kDcBase = 0x0900;
inline constexpr std::uint16_t kDcEnd = 0x0A00;
inline constexpr std::uint16_t kDigitalIoOutput = 0x0F00;
inline constexpr std::uint16_t kProcessRam = 0x1000;

// Offsets inside one sync manager's 8-byte register block (0x0800 + 8n).
namespace sm {
inline constexpr std::uint16_t kStartAddress = 0;  // 2 bytes
inline constexpr std::uint16_t kLength = 2;        // 2 bytes
inline constexpr std::uint16_t kControl = 4;
inline constexpr std::uint16_t kStatus = 5;
inline constexpr std::uint16_t kActivate = 6;
inline constexpr std::uint16_t kPdiControl = 7;
}  // namespace sm

constexpr std::uint16_t sync_manager(unsigned n) noexcept {
  return static_cast<std::uint16_t>(kSyncManagerBase + n * kSyncManagerStride);
}
constexpr std::uint16_t fmmu(unsigned n) noexcept {
  return static_cast<std::uint16_t>(kFmmuBase + n * kFmmuStride);
}

}  // namespace ecat::esc::reg
