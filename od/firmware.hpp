// Whether a µC runs behind the ESC of a device (the twin's firmware).
#pragma once

#include <cstdint>

#include "od/device.hpp"

namespace ecat::od {

// PDI type 0 (0x0140 = SII word 0 low byte; Section II 0x0140: interface
// deactivated) means no µC: couplers and junctions, whose ESC only forwards.
// But only firmware answers a mailbox, so a device that gives mailbox SMs has
// one whatever word 0 says (Bohign DM556EC's ConfigData 003C...: PDI type 0
// next to a CoE mailbox; docs/twins.md "PDI type 0 with a mailbox").
inline constexpr std::uint16_t kPdiTypeMask = 0x00FF;
inline bool has_mailbox_sm(const DeviceDescription& d) noexcept {
  for (const auto& sm : d.sync_managers) {
    if (sm.type == SmType::MailboxOut || sm.type == SmType::MailboxIn) return true;
  }
  return false;
}
inline bool runs_firmware(const DeviceDescription& d) noexcept {
  return (d.esc.pdi_control & kPdiTypeMask) != 0 || has_mailbox_sm(d);
}

}  // namespace ecat::od
