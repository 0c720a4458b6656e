// The ESC address space as either side sees it: registers below 0x1000,
// process RAM above, and sync-manager buffers guarding parts of the RAM
// (Section I §8; ETG.1000.4 §5.4.3 "accessible memory" for the WKC).
// RAM not covered by an enabled SM is freely accessible from both sides.
#include <algorithm>
#include <bit>
#include <cstring>

#include "esc/esc.hpp"
#include "esc/registers.hpp"
#include "esc/small_copy.hpp"

namespace ecat::esc {

namespace {

// The SM guarding `pos`, or the start of the next guarded area (`limit` if none).
struct Guard {
  int sm = -1;
  std::uint32_t end = 0;
};

// `enabled`: bit n set for every enabled SM n (Esc::sm_enabled_), lowest first.
template <typename Sms>
Guard find_guard(const Sms& sms, std::uint32_t enabled, std::uint32_t pos, std::uint32_t limit) noexcept {
  Guard g{-1, limit};
  for (std::uint32_t left = enabled; left != 0; left &= left - 1) {
    const auto n = static_cast<unsigned>(std::countr_zero(left));
    const SyncManager& sm = sms[n];
    const std::uint32_t start = sm.start();
    const std::uint32_t end = sm.end();
    if (pos >= start && pos < end) return Guard{static_cast<int>(n), std::min(limit, end)};
    if (start > pos) g.end = std::min(g.end, start);
  }
  return g;
}

}  // namespace

bool Esc::mem_read(std::uint16_t address, std::span<std::uint8_t> out, Side side) noexcept {
  const std::uint32_t end = std::min<std::uint32_t>(address + static_cast<std::uint32_t>(out.size()), kAddressSpace);
  if (end <= reg::kProcessRam) return reg_read(address, out, side);  // registers only
  std::uint32_t pos = address;
  bool any = false;
  if (pos < reg::kProcessRam) {
    const std::uint32_t seg = std::min<std::uint32_t>(end, reg::kProcessRam);
    any = reg_read(address, out.first(seg - pos), side);
    pos = seg;
  }
  const std::uint32_t limit = std::min(end, ram_end());
  while (pos < limit) {
    const Guard g = find_guard(sms_, sm_enabled_, pos, limit);
    auto part = out.subspan(pos - address, g.end - pos);
    if (g.sm < 0) {
      copy_small(part.data(), mem_.get() + pos, part.size());
      any = true;
    } else {
      SmSignals sig;
      any = sms_[g.sm].read(side, static_cast<std::uint16_t>(pos), part, sig) || any;
      apply(static_cast<unsigned>(g.sm), sig);
    }
    pos = g.end;
  }
  return any;  // bytes past the RAM are not accessible: data untouched, not counted
}

bool Esc::mem_write(std::uint16_t address, std::span<const std::uint8_t> in, Side side) noexcept {
  const std::uint32_t end = std::min<std::uint32_t>(address + static_cast<std::uint32_t>(in.size()), kAddressSpace);
  // Section II 0x0802: an ECAT write to the byte of a 1-byte SM (in RAM or
  // e.g. the digital outputs 0x0F00) restarts the process-data watchdog.
  if (side == Side::Ecat && sm_watchdog_only_ != 0) restart_watchdog_over(address, end - address);
  if (end <= reg::kProcessRam) return reg_write(address, in, side);  // registers only
  std::uint32_t pos = address;
  bool any = false;
  if (pos < reg::kProcessRam) {
    const std::uint32_t seg = std::min<std::uint32_t>(end, reg::kProcessRam);
    any = reg_write(address, in.first(seg - pos), side);
    pos = seg;
  }
  // ESC write protection (0x0031) covers the RAM too (Section I §13).
  if (side == Side::Ecat && (mem_[reg::kEscWriteProtection] & bits::kWriteProtect) && !esc_write_enabled_) {
    return any;
  }
  const std::uint32_t limit = std::min(end, ram_end());
  while (pos < limit) {
    const Guard g = find_guard(sms_, sm_enabled_, pos, limit);
    auto part = in.subspan(pos - address, g.end - pos);
    if (g.sm < 0) {
      copy_small(mem_.get() + pos, part.data(), part.size());  // often a 2- or 4-byte FPWR
      any = true;
    } else {
      SmSignals sig;
      any = sms_[g.sm].write(side, static_cast<std::uint16_t>(pos), part, sig) || any;
      apply(static_cast<unsigned>(g.sm), sig);
    }
    pos = g.end;
  }
  return any;
}

void Esc::peek(std::uint32_t address, std::span<std::uint8_t> out) const noexcept {
  for (std::size_t i = 0; i < out.size(); ++i) {
    const std::uint32_t a = address + static_cast<std::uint32_t>(i);
    out[i] = a < ram_end() ? mem_[a] : 0;  // not present beyond the RAM
  }
}

}  // namespace ecat::esc
