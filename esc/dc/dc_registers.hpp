// Distributed-clocks registers, as offsets from 0x0900 (ESC datasheet
// Section II §10 "Distributed Clocks"; shared/spec/esc-registers.md §10).
#pragma once

#include <cstdint>

namespace ecat::esc::dcreg {

inline constexpr std::uint16_t kReceiveTimePort0 = 0x00;  // 4 bytes per port
inline constexpr std::uint16_t kReceiveTimePortStride = 0x04;
inline constexpr std::uint16_t kSystemTime = 0x10;                // 8
inline constexpr std::uint16_t kReceiveTimeProcessingUnit = 0x18;  // 8
inline constexpr std::uint16_t kSystemTimeOffset = 0x20;          // 8
inline constexpr std::uint16_t kSystemTimeDelay = 0x28;           // 4
inline constexpr std::uint16_t kSystemTimeDifference = 0x2C;      // 4
inline constexpr std::uint16_t kSpeedCounterStart = 0x30;         // 2
inline constexpr std::uint16_t kSpeedCounterDiff = 0x32;          // 2
inline constexpr std::uint16_t kSystemTimeDiffFilterDepth = 0x34;
inline constexpr std::uint16_t kSpeedCounterFilterDepth = 0x35;
inline constexpr std::uint16_t kCyclicUnitControl = 0x80;
inline constexpr std::uint16_t kActivation = 0x81;
inline constexpr std::uint16_t kSyncPulseLength = 0x82;           // 2
inline constexpr std::uint16_t kActivationStatus = 0x84;
inline constexpr std::uint16_t kSync0Status = 0x8E;
inline constexpr std::uint16_t kSync1Status = 0x8F;
inline constexpr std::uint16_t kStartTimeCyclicOperation = 0x90;  // 8
inline constexpr std::uint16_t kNextSync1Pulse = 0x98;            // 8
inline constexpr std::uint16_t kSync0CycleTime = 0xA0;            // 4
inline constexpr std::uint16_t kSync1CycleTime = 0xA4;            // 4
inline constexpr std::uint16_t kLatch0Control = 0xA8;
inline constexpr std::uint16_t kLatch1Control = 0xA9;
inline constexpr std::uint16_t kLatch0Status = 0xAE;
inline constexpr std::uint16_t kLatch1Status = 0xAF;
inline constexpr std::uint16_t kLatch0TimePositive = 0xB0;        // 8
inline constexpr std::uint16_t kLatch0TimeNegative = 0xB8;        // 8
inline constexpr std::uint16_t kLatch1TimePositive = 0xC0;        // 8
inline constexpr std::uint16_t kLatch1TimeNegative = 0xC8;        // 8
inline constexpr std::uint16_t kBlockEnd = 0x100;

// 0x0980 cyclic unit control.
inline constexpr std::uint8_t kSyncOwnerPdi = 0x01;     // bit 0
inline constexpr std::uint8_t kLatch0OwnerPdi = 0x10;   // bit 4
inline constexpr std::uint8_t kLatch1OwnerPdi = 0x20;   // bit 5
// 0x0981 activation.
inline constexpr std::uint8_t kActivateSyncUnit = 0x01;
inline constexpr std::uint8_t kActivateSync0 = 0x02;
inline constexpr std::uint8_t kActivateSync1 = 0x04;
inline constexpr std::uint8_t kAutoActivation = 0x08;
inline constexpr std::uint8_t kStartTimeExtension = 0x10;
inline constexpr std::uint8_t kStartTimePlausibility = 0x20;
inline constexpr std::uint8_t kNearFutureShort = 0x40;
inline constexpr std::uint8_t kDebugPulse = 0x80;
// 0x0984 activation status.
inline constexpr std::uint8_t kFirstSync0Pending = 0x01;
inline constexpr std::uint8_t kFirstSync1Pending = 0x02;
inline constexpr std::uint8_t kStartTimeOutOfNearFuture = 0x04;
// 0x09AE/0x09AF latch status.
inline constexpr std::uint8_t kLatchPositiveEvent = 0x01;
inline constexpr std::uint8_t kLatchNegativeEvent = 0x02;
inline constexpr std::uint8_t kLatchPinState = 0x04;
// 0x09A8/0x09A9 latch control: 1 = single event, 0 = continuous.
inline constexpr std::uint8_t kLatchPositiveSingle = 0x01;
inline constexpr std::uint8_t kLatchNegativeSingle = 0x02;

// AL event request 0x0220 / ECAT event request 0x0210 bits the unit drives.
inline constexpr std::uint32_t kAlEventLatch = 1u << 1;
inline constexpr std::uint32_t kAlEventSync0 = 1u << 2;
inline constexpr std::uint32_t kAlEventSync1 = 1u << 3;
inline constexpr std::uint16_t kEcatEventLatch = 1u << 0;

// Reset values (Section II): speed counter start 0x1000, filter depths 4/12.
inline constexpr std::uint16_t kSpeedCounterStartReset = 0x1000;
inline constexpr std::uint8_t kSystemTimeDiffFilterDepthReset = 4;
inline constexpr std::uint8_t kSpeedCounterFilterDepthReset = 12;

}  // namespace ecat::esc::dcreg
