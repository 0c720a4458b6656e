// Whether a device can carry process data in a direction at all (issue 14,
// docs/twins.md "An enabled SM for a direction without process data").
#pragma once

#include <cstdint>

#include "od/device.hpp"

namespace ecat::od {

// Whether the device can carry process data in a direction at all: it has a
// PDO of that direction, or a mapping object (1600h-17FFh for outputs,
// 1A00h-1BFFh for inputs) a master could assign. A device without (an
// inputs-only NI 9144 has SM2 but no RxPDO) is firmware built without that
// direction: SSC compiled with MAX_PD_OUTPUT_SIZE 0 does not check SM2
// (docs/twins.md).
inline bool has_process_data(const DeviceDescription& device, bool outputs) noexcept {
  if (!(outputs ? device.rx_pdos : device.tx_pdos).empty()) return true;
  // CiA 301 §7.4.8: RxPDO mapping 1600h-17FFh, TxPDO mapping 1A00h-1BFFh.
  constexpr std::uint16_t kRxFirst = 0x1600, kRxLast = 0x17FF, kTxFirst = 0x1A00, kTxLast = 0x1BFF;
  const std::uint16_t first = outputs ? kRxFirst : kTxFirst;
  const std::uint16_t last = outputs ? kRxLast : kTxLast;
  for (const Object& o : device.dictionary.objects()) {
    if (o.index >= first && o.index <= last) return true;
  }
  return false;
}

}  // namespace ecat::od
