// Bits of the ESC registers the CoE layer reads through the PDI (Beckhoff ESC
// datasheet Section II §3.45 / §3.54, ETG.1000.4 §6.7; shared/spec/esc-registers.md
// §4.8, §4.10, §7). Kept here, beside their only users, rather than in esc/.
#pragma once

#include <cstdint>

namespace ecat::coe::bits {

inline constexpr std::uint8_t kAlStateMask = 0x0F;           // 0x0130 bits 3:0
inline constexpr std::uint8_t kSmStatusMailboxFull = 1u << 3;  // 0x0805+8n bit 3
inline constexpr std::uint8_t kSmActivateEnable = 1u << 0;     // 0x0806+8n bit 0
inline constexpr std::uint8_t kSmActivateRepeatRequest = 1u << 1;  // 0x0806+8n bit 1
inline constexpr std::uint8_t kSmPdiDeactivate = 1u << 0;      // 0x0807+8n bit 0
inline constexpr std::uint8_t kSmPdiRepeatAck = 1u << 1;       // 0x0807+8n bit 1
inline constexpr std::uint32_t kAlEventSmBase = 1u << 8;       // 0x0220 bit 8+n: SMn event

constexpr std::uint32_t al_event_sm(unsigned n) noexcept { return kAlEventSmBase << n; }

}  // namespace ecat::coe::bits
