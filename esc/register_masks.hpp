// Which bits of each register byte 0x0000-0x0FFF the EtherCAT side and the
// PDI may write (Beckhoff ESC datasheet Section II, the "ECAT"/"PDI" access
// columns; shared/spec/esc-registers.md §3-§4). Side effects beyond storing
// the value are in esc/register_access.cpp.
#pragma once

#include <cstdint>

#include "esc/esc_config.hpp"
#include "esc/register_bits.hpp"
#include "esc/registers.hpp"

namespace ecat::esc {

// Register blocks and fields named by the masks and the side effects.
namespace reg_layout {
inline constexpr std::uint16_t kMiiControl = 0x0510;
inline constexpr std::uint16_t kMiiPhyAddress = 0x0512;
inline constexpr std::uint16_t kMiiEcatAccess = 0x0516;
inline constexpr std::uint16_t kMiiPdiAccess = 0x0517;
inline constexpr std::uint16_t kMiiEnd = 0x0518;
// 0x0510-0x0511 MII management control/status: bit 0 write enable, bits 9:8
// command (0 idle/clear errors, 1 read, 2 write), bit 13 read error (PHY not
// responding), bit 14 command error, bit 15 busy.
inline constexpr std::uint8_t kMiiWriteEnable = 0x01;
inline constexpr std::uint8_t kMiiCommandMask = 0x03;  // in the high byte
inline constexpr std::uint8_t kMiiCommandRead = 0x01;
inline constexpr std::uint8_t kMiiCommandWrite = 0x02;
inline constexpr std::uint8_t kMiiReadError = 0x20;     // high byte bit 5 = bit 13
inline constexpr std::uint8_t kMiiCommandError = 0x40;  // high byte bit 6 = bit 14
inline constexpr std::uint8_t kLedOverrideWritable = 0x1F;
inline constexpr std::uint8_t kSmControlWritable = 0x7F;
inline constexpr std::uint8_t kFmmuTypeWritable = 0x03;
// The FMMU and SM blocks (0x0700-0x07FF and 0x0880-0x08FF are reserved).
inline constexpr std::uint16_t kFmmuEnd = reg::kFmmuBase + kMaxFmmus * reg::kFmmuStride;
inline constexpr std::uint16_t kSmEnd = reg::kSyncManagerBase + kMaxSyncManagers * reg::kSyncManagerStride;
}  // namespace reg_layout

struct RegisterWriteMask {
  std::uint8_t ecat = 0;
  std::uint8_t pdi = 0;
};

// The masks of register bytes outside the FMMU and SM blocks, which do not
// depend on the configuration (usable in constant expressions: the
// register map of esc/register_map.hpp is built from it).
constexpr RegisterWriteMask fixed_register_write_mask(std::uint16_t a) noexcept {
  using namespace reg;
  using namespace reg_layout;
  constexpr RegisterWriteMask kEcat{0xFF, 0x00};
  constexpr RegisterWriteMask kPdi{0x00, 0xFF};
  constexpr RegisterWriteMask kBoth{0xFF, 0xFF};
  switch (a) {
    case kConfiguredStationAddress:
    case kConfiguredStationAddress + 1: return kEcat;
    case kConfiguredStationAlias:
    case kConfiguredStationAlias + 1: return kPdi;
    case kRegisterWriteEnable:
    case kRegisterWriteProtection:
    case kEscWriteEnable:
    case kEscWriteProtection: return {bits::kWriteEnable, 0};
    case kEscResetEcat: return kEcat;
    case kEscResetPdi: return kPdi;
    case kDlControl: return {0x03, 0};
    case kDlControl + 1: return kEcat;
    case kDlControl + 2: return {0x0F, 0};
    case kDlControl + 3: return {0x01, 0};
    case kPhysicalRwOffset:
    case kPhysicalRwOffset + 1: return kEcat;
    case kAlControl: return {bits::kAlControlWritable, 0};
    case kAlStatus: return {0, bits::kAlStatusWritable};
    case kAlStatusCode:
    case kAlStatusCode + 1: return kPdi;
    case kRunLedOverride:
    case kErrLedOverride: return {kLedOverrideWritable, 0};
    case kEcatEventMask:
    case kEcatEventMask + 1: return kEcat;
    case kAlEventMask:
    case kAlEventMask + 1:
    case kAlEventMask + 2:
    case kAlEventMask + 3: return kPdi;
    case kWatchdogDivider:
    case kWatchdogDivider + 1:
    case kWatchdogTimePdi:
    case kWatchdogTimePdi + 1:
    case kWatchdogTimeProcessData:
    case kWatchdogTimeProcessData + 1: return kEcat;
    case kMiiControl: return {kMiiWriteEnable, 0};
    case kMiiControl + 1: return {kMiiCommandMask, 0};
    case kMiiPhyAddress:
    case kMiiPhyAddress + 1:
    case kMiiPhyAddress + 2:
    case kMiiPhyAddress + 3: return kBoth;
    case kMiiEcatAccess: return {0x01, 0};
    case kMiiPdiAccess: return {0, 0x01};
    default: break;
  }
  if (a >= kDigitalIoOutput && a < bits::kDigitalOutputEnd) return kEcat;
  if (a >= bits::kUserRam && a < kProcessRam) return kBoth;
  return {};
}

// Bits of register byte `address` (< 0x1000, outside 0x0500-0x050F and the
// DC block, which have their own handlers) each side may write.
RegisterWriteMask register_write_mask(std::uint16_t address, const EscConfig& config) noexcept;

}  // namespace ecat::esc
