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
  return fixed_register_write_mask(a);
}

}  // namespace ecat::esc
