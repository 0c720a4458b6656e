// Bit meanings of the ESC registers the emulator acts on (Beckhoff ESC
// datasheet Section II; shared/spec/esc-registers.md §4). Addresses are in
// esc/registers.hpp.
#pragma once

#include <cstdint>

namespace ecat::esc::bits {

// 0x0008 ESC features supported.
inline constexpr std::uint16_t kFeatureDc = 1u << 2;
inline constexpr std::uint16_t kFeatureDc64 = 1u << 3;
inline constexpr std::uint16_t kFeatureEnhancedDcSync = 1u << 8;
inline constexpr std::uint16_t kFeatureNoLrw = 1u << 9;
inline constexpr std::uint16_t kFeatureNoReadWrite = 1u << 10;

// 0x0020 / 0x0030 write enable, 0x0021 / 0x0031 write protection.
inline constexpr std::uint8_t kWriteEnable = 0x01;
inline constexpr std::uint8_t kWriteProtect = 0x01;
inline constexpr std::uint16_t kWriteProtectedEnd = 0x0F80;  // 0x0F80.. user RAM is never protected

// 0x0040 / 0x0041 ESC reset sequence 'R' 'E' 'S'.
inline constexpr std::uint8_t kResetSequence[3] = {0x52, 0x45, 0x53};

// 0x0100 DL control (32 bit).
inline constexpr std::uint32_t kDlForwardingRule = 1u << 0;
inline constexpr unsigned kDlLoopShift = 8;  // 2 bits per port
inline constexpr std::uint32_t kDlLoopMask = 0x3;
inline constexpr std::uint32_t kLoopAuto = 0;
inline constexpr std::uint32_t kLoopAutoClose = 1;
inline constexpr std::uint32_t kLoopOpen = 2;
inline constexpr std::uint32_t kLoopClosed = 3;
inline constexpr std::uint32_t kDlRxFifoReset = 7u << 16;
inline constexpr std::uint32_t kDlStationAlias = 1u << 24;
// Reset value: non-EtherCAT frames destroyed, all ports Auto, RX FIFO size 7.
inline constexpr std::uint32_t kDlControlReset = kDlForwardingRule | kDlRxFifoReset;

// 0x0110 DL status.
inline constexpr std::uint16_t kDlPdiOperational = 1u << 0;
inline constexpr std::uint16_t kDlPdiWatchdogOk = 1u << 1;
inline constexpr std::uint16_t kDlEnhancedLinkDetection = 1u << 2;
inline constexpr unsigned kDlPhysicalLinkShift = 4;  // bit 4 + port
inline constexpr unsigned kDlLoopClosedShift = 8;    // bit 8 + 2 port
inline constexpr unsigned kDlCommunicationShift = 9; // bit 9 + 2 port

// 0x0120 AL control / 0x0130 AL status.
inline constexpr std::uint8_t kAlControlWritable = 0x3F;  // state, ack, id request
inline constexpr std::uint8_t kAlStatusWritable = 0x3F;   // state, ErrInd, id loaded
inline constexpr std::uint8_t kAlStateMask = 0x0F;
inline constexpr std::uint8_t kAlErrorInd = 0x10;         // AL status bit 4 / AL control bit 4 (ack)
inline constexpr std::uint16_t kAlStatusReset = 0x0001;   // Init
inline constexpr std::uint16_t kAlControlReset = 0x0001;

// 0x0141 ESC configuration.
inline constexpr std::uint8_t kEscConfigDeviceEmulation = 0x01;
inline constexpr std::uint8_t kEscConfigEnhancedLink = 0x02;
// Bits a master-commanded EEPROM reload leaves alone (Section I §11.1).
inline constexpr std::uint8_t kEscConfigKeptOnReload = 0xF2;

// 0x0210 ECAT event request / 0x0200 mask.
inline constexpr std::uint16_t kEcatEventDcLatch = 1u << 0;
inline constexpr std::uint16_t kEcatEventDlStatus = 1u << 2;
inline constexpr std::uint16_t kEcatEventAlStatus = 1u << 3;
inline constexpr unsigned kEcatEventSmShift = 4;  // SM0..SM7 -> bits 4..11
inline constexpr unsigned kEcatEventSmCount = 8;

// 0x0220 AL event request / 0x0204 mask.
inline constexpr std::uint32_t kAlEventAlControl = 1u << 0;
inline constexpr std::uint32_t kAlEventSmActivation = 1u << 4;
inline constexpr std::uint32_t kAlEventEeprom = 1u << 5;
inline constexpr std::uint32_t kAlEventWatchdog = 1u << 6;
inline constexpr unsigned kAlEventSmShift = 8;  // SM0..SM15 -> bits 8..23

// 0x0300.. error counters.
inline constexpr std::uint16_t kRxErrorCountersEnd = 0x030C;  // 0x0300-0x030B cleared together
inline constexpr std::uint16_t kLostLinkCountersEnd = 0x0314;
inline constexpr std::uint8_t kCounterMax = 0xFF;

// 0x0440 watchdog status process data.
inline constexpr std::uint8_t kWatchdogPdActive = 0x01;

// 0x0F00-0x0F03 digital I/O output data, 0x0F80-0x0FFF user RAM.
inline constexpr std::uint16_t kDigitalOutputEnd = 0x0F04;
inline constexpr std::uint16_t kUserRam = 0x0F80;

}  // namespace ecat::esc::bits
