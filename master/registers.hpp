// ESC register addresses and bits the master uses (ESC datasheet Section II;
// shared/spec/esc-registers.md). The master layer may not include esc/, so
// these are named here again, in the same words as esc/registers.hpp.
#pragma once

#include <cstdint>

namespace ecat::master::reg {

inline constexpr std::uint16_t kType = 0x0000;
inline constexpr std::uint16_t kEscInfoLength = 10;  // 0x0000-0x0009
inline constexpr std::uint16_t kConfiguredStationAddress = 0x0010;
inline constexpr std::uint16_t kConfiguredStationAlias = 0x0012;
// Write protection (ESC datasheet Section I "Write protection", Section II
// 0x0020/0x0021, 0x0030/0x0031): bit 0 of an enable register releases the
// protection for the rest of the frame it is written in.
inline constexpr std::uint16_t kRegisterWriteEnable = 0x0020;
inline constexpr std::uint16_t kRegisterWriteProtection = 0x0021;
inline constexpr std::uint16_t kEscWriteEnable = 0x0030;
inline constexpr std::uint16_t kEscWriteProtection = 0x0031;
inline constexpr std::uint8_t kWriteEnableBit = 0x01;
inline constexpr std::uint16_t kDlControl = 0x0100;
inline constexpr std::uint16_t kDlControlLoop = 0x0101;
inline constexpr std::uint16_t kDlControlAlias = 0x0103;
inline constexpr std::uint16_t kDlStatus = 0x0110;
inline constexpr std::uint16_t kAlControl = 0x0120;
inline constexpr std::uint16_t kAlStatus = 0x0130;
inline constexpr std::uint16_t kAlStatusReadLength = 6;  // 0x0130-0x0135: status + code
inline constexpr std::uint16_t kAlStatusCode = 0x0134;
inline constexpr std::uint16_t kEcatEventMask = 0x0200;
inline constexpr std::uint16_t kRxErrorCounter = 0x0300;
inline constexpr std::uint16_t kWatchdogDivider = 0x0400;
inline constexpr std::uint16_t kWatchdogTimeProcessData = 0x0420;
inline constexpr std::uint16_t kEepromConfiguration = 0x0500;
inline constexpr std::uint16_t kEepromControlStatus = 0x0502;
inline constexpr std::uint16_t kEepromAddress = 0x0504;
inline constexpr std::uint16_t kEepromData = 0x0508;
inline constexpr std::uint16_t kFmmuBase = 0x0600;
inline constexpr std::uint16_t kFmmuSize = 16;
inline constexpr std::uint16_t kFmmuBlockSize = 256;  // 16 FMMUs
inline constexpr std::uint16_t kSyncManagerBase = 0x0800;
inline constexpr std::uint16_t kSyncManagerSize = 8;
inline constexpr std::uint16_t kSyncManagerBlockSize = 256;  // 32 SMs
inline constexpr std::uint16_t kSmControlOffset = 4;
inline constexpr std::uint16_t kSmStatusOffset = 5;
inline constexpr std::uint16_t kSmActivateOffset = 6;
inline constexpr std::uint16_t kSmPdiControlOffset = 7;

// DC (0x0900-0x09FF).
inline constexpr std::uint16_t kDcPortReceiveTime = 0x0900;  // 4 x 4 bytes
inline constexpr std::uint16_t kDcSystemTime = 0x0910;
inline constexpr std::uint16_t kDcProcessingUnitReceiveTime = 0x0918;
inline constexpr std::uint16_t kDcSystemTimeOffset = 0x0920;
inline constexpr std::uint16_t kDcSystemTimeDelay = 0x0928;
inline constexpr std::uint16_t kDcSystemTimeDifference = 0x092C;
inline constexpr std::uint16_t kDcSpeedCounterStart = 0x0930;
inline constexpr std::uint16_t kDcCyclicUnitControl = 0x0980;
inline constexpr std::uint16_t kDcActivation = 0x0981;
inline constexpr std::uint16_t kDcStartTime = 0x0990;
inline constexpr std::uint16_t kDcSync0CycleTime = 0x09A0;
inline constexpr std::uint16_t kDcSync1CycleTime = 0x09A4;

// 0x0502 EEPROM control/status bits.
inline constexpr std::uint16_t kEepromReadSize8 = 0x0040;  // bit 6: reads return 8 bytes
inline constexpr std::uint16_t kEepromCmdRead = 0x0100;
inline constexpr std::uint16_t kEepromCmdMask = 0x0700;
inline constexpr std::uint16_t kEepromChecksumError = 0x0800;
inline constexpr std::uint16_t kEepromLoading = 0x1000;
inline constexpr std::uint16_t kEepromAckError = 0x2000;
inline constexpr std::uint16_t kEepromWriteEnableError = 0x4000;
inline constexpr std::uint16_t kEepromBusy = 0x8000;
inline constexpr std::uint16_t kEepromErrorBits = kEepromAckError | kEepromWriteEnableError;

// SM status / activate / PDI control bits.
inline constexpr std::uint8_t kSmStatusMailboxFull = 0x08;  // status bit 3
inline constexpr std::uint8_t kSmControlWatchdogTrigger = 0x40;  // control bit 6 (ESC Section II 0x0804)
inline constexpr std::uint8_t kSmActivateEnable = 0x01;
inline constexpr std::uint8_t kSmActivateRepeat = 0x02;     // repeat request
inline constexpr std::uint8_t kSmPdiRepeatAck = 0x02;       // repeat acknowledge

// FMMU type bits.
inline constexpr std::uint8_t kFmmuRead = 0x01;
inline constexpr std::uint8_t kFmmuWrite = 0x02;

// DC activation 0x0981.
inline constexpr std::uint8_t kDcActivateCyclic = 0x01;
inline constexpr std::uint8_t kDcActivateSync0 = 0x02;
inline constexpr std::uint8_t kDcActivateSync1 = 0x04;

constexpr std::uint16_t sync_manager(unsigned n) noexcept {
  return static_cast<std::uint16_t>(kSyncManagerBase + n * kSyncManagerSize);
}
constexpr std::uint16_t fmmu(unsigned n) noexcept {
  return static_cast<std::uint16_t>(kFmmuBase + n * kFmmuSize);
}

}  // namespace ecat::master::reg
