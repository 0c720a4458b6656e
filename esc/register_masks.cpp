// Per-side write masks of the register bytes (Section II access columns).
#include "esc/register_masks.hpp"

#include "esc/fmmu.hpp"
#include "esc/register_bits.hpp"
#include "esc/sync_manager.hpp"

namespace ecat::esc {

using namespace reg_layout;

// Bits of register byte `a` each side may write (Section II). Registers
// with side effects beyond storing are handled in after_register_write.
RegisterWriteMask register_write_mask(std::uint16_t a, const EscConfig& cfg) noexcept {
  using namespace reg;
  constexpr RegisterWriteMask kEcat{0xFF, 0x00};
  constexpr RegisterWriteMask kPdi{0x00, 0xFF};
  constexpr RegisterWriteMask kBoth{0xFF, 0xFF};
  if (a >= kFmmuBase && a < kFmmuEnd) {
    const unsigned n = (a - kFmmuBase) / kFmmuStride;
    const unsigned off = (a - kFmmuBase) % kFmmuStride;
    if (n >= cfg.fmmu_count) return {};
    switch (off) {
      case fmmu_reg::kLogicalStartBit:
      case fmmu_reg::kLogicalStopBit:
      case fmmu_reg::kPhysicalStartBit: return {fmmu_reg::kBitMask, 0};
      case fmmu_reg::kType: return {kFmmuTypeWritable, 0};
      case fmmu_reg::kActivate: return {fmmu_reg::kActivateEnable, 0};
      default: return off < fmmu_reg::kActivate ? kEcat : RegisterWriteMask{};
    }
  }
  if (a >= kSyncManagerBase && a < kSmEnd) {
    const unsigned n = (a - kSyncManagerBase) / kSyncManagerStride;
    const unsigned off = (a - kSyncManagerBase) % kSyncManagerStride;
    if (n >= cfg.sync_manager_count) return {};
    switch (off) {
      case sm::kControl: return {kSmControlWritable, 0};
      case sm::kStatus: return {};
      case sm::kActivate: return {sm_bits::kActivateWritable, 0};
      case sm::kPdiControl: return {0, sm_bits::kPdiControlWritable};
      default: return kEcat;
    }
  }
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

}  // namespace ecat::esc
