// FMMU register decoding (Section II 0x0600+16n).
#include "esc/fmmu.hpp"

#include "common/le.hpp"

namespace ecat::esc {

Fmmu Fmmu::decode(const std::uint8_t* block) noexcept {
  using namespace fmmu_reg;
  Fmmu f;
  f.logical_start = load_le<std::uint32_t>(block + kLogicalStart);
  f.length = load_le<std::uint16_t>(block + kLength);
  f.logical_start_bit = static_cast<std::uint8_t>(block[kLogicalStartBit] & kBitMask);
  f.logical_stop_bit = static_cast<std::uint8_t>(block[kLogicalStopBit] & kBitMask);
  f.physical_start = load_le<std::uint16_t>(block + kPhysicalStart);
  f.physical_start_bit = static_cast<std::uint8_t>(block[kPhysicalStartBit] & kBitMask);
  f.read = (block[kType] & kTypeRead) != 0;
  f.write = (block[kType] & kTypeWrite) != 0;
  f.enabled = (block[kActivate] & kActivateEnable) != 0;
  return f;
}

bool Fmmu::byte_aligned() const noexcept {
  return logical_start_bit == 0 && logical_stop_bit == 7 && physical_start_bit == 0;
}

}  // namespace ecat::esc
