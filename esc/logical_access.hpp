// Logical addressing through the FMMUs, per-frame part (ESC datasheet
// Section I §6; ETG.1000.4 §5.4.3): inline, so that it compiles into the
// frame pass (esc/datagram_engine.hpp). The decoding of the FMMUs into
// routes and the bit-granular general path are in esc/logical_access.cpp.
// Internal header: only the datagram engine includes it.
#pragma once

#include <algorithm>
#include <cstring>

#include "common/cache_line.hpp"
#include "esc/datagram_rules.hpp"
#include "esc/esc.hpp"
#include "esc/registers.hpp"

namespace ecat::esc {

namespace logical_detail {
// Plain RAM through a byte FMMU: one byte (the digital I/O of a
// terminal) as a move, the rest through memcpy - a smaller body than
// copy_small's, in a path every frame pass inlines.
inline void copy_bytes(std::uint8_t* dst, const std::uint8_t* src, std::size_t n) noexcept {
  if (n == 1) {
    *dst = *src;
  } else {
    std::memcpy(dst, src, n);
  }
}

inline std::uint16_t wkc_of(Command cmd, bool read_hit, bool write_hit) noexcept {
  std::uint16_t wkc = 0;
  if (read_hit) wkc = static_cast<std::uint16_t>(wkc + kWkcRead);
  if (write_hit) wkc = static_cast<std::uint16_t>(wkc + (cmd == Command::Lrw ? kWkcReadWriteWrite : kWkcWrite));
  return wkc;
}
}  // namespace logical_detail

// First a quick reject: a datagram that misses the logical span of every
// active FMMU of this ESC (logical_first_/logical_end_, kept by
// update_fmmus) does nothing here - the common case for the ESCs an LRW
// passes by; an ESC without LRW support (0x0008 bit 9) lets LRW pass untouched. Then the routed path: per FMMU a range compare and one copy
// through its SM. All reads, then all writes, each in FMMU order, as the
// general path.
[[gnu::always_inline]] inline std::uint16_t Esc::process_logical(DatagramView d) noexcept {
  const std::uint64_t dg0 = d.logical_address();
  const std::size_t size = d.length();
  if (dg0 >= logical_end_ || dg0 + size <= logical_first_ || size == 0) return 0;
  if (d.command() == Command::Lrw && !config_.lrw) return 0;  // 0x0008 bit 9: passes untouched
  if (!fmmus_routed_) return process_logical_bits(d);
  return process_logical_routes(d);
}

// The members the pass of a frame reads first: the configuration (LRW
// support), the routes and their counts, the logical span, the line route
// and the pass hook - five lines of the object, wherever the members move.
inline void Esc::prefetch_pass_object() const noexcept {
  __builtin_prefetch(&config_);
  __builtin_prefetch(&routes_);
  __builtin_prefetch(&route_reads_);
  __builtin_prefetch(&logical_first_);
  __builtin_prefetch(&line_route_);
  __builtin_prefetch(&hook_.synced);
}

// What those members point to, read once the object's lines are in: the
// routes, the SMs the process data goes through (SM2, SM3), and the register
// lines a mapped access reads or writes (write protection, the event
// requests, the SM registers). The 3-buffers themselves were not worth it
// (measured: no gain).
inline void Esc::prefetch_pass_targets() const noexcept {
  constexpr std::size_t kSmsPerLine = std::max<std::size_t>(1, kCacheLineBytes / sizeof(SyncManager));
  __builtin_prefetch(routes_);
  __builtin_prefetch(write_routes_);
  __builtin_prefetch(sms_ + kSmsPerLine);
  const std::uint8_t* m = mem_.get();
  __builtin_prefetch(m + reg::kEscWriteProtection);
  __builtin_prefetch(m + reg::kEcatEventRequest);
  __builtin_prefetch(m + reg::sync_manager(0));
}

// The events of a whole-buffer SM access by ECAT (see Esc::whole_route).
[[gnu::always_inline]] inline void Esc::whole_events(const FmmuRoute& r) noexcept {
  std::uint8_t* m = mem_.get();
  if (r.al_raise != 0) store_le(m + reg::kAlEventRequest, load_le<std::uint32_t>(m + reg::kAlEventRequest) | r.al_raise);
  if (r.ecat_clear != 0) {
    store_le(m + reg::kEcatEventRequest,
             static_cast<std::uint16_t>(load_le<std::uint16_t>(m + reg::kEcatEventRequest) & ~r.ecat_clear));
  }
  if (r.watchdog) restart_process_data_watchdog();
}

inline std::uint16_t Esc::process_logical_routes(DatagramView d) noexcept {
  const Command cmd = d.command();
  Bytes data = d.data();
  const std::uint64_t dg0 = d.logical_address();
  const std::uint64_t dg1 = dg0 + data.size();
  bool read_hit = false;
  bool write_hit = false;
  if (cmd != Command::Lwr) {
    for (unsigned i = 0; i < route_reads_; ++i) {
      const FmmuRoute& r = routes_[i];
      const std::uint64_t lo = std::max(dg0, r.first);
      const std::uint64_t hi = std::min(dg1, r.end);
      if (lo >= hi) continue;
      const std::uint64_t paddr = r.physical + (lo - r.first);
      if (paddr >= kAddressSpace) continue;
      const std::span<std::uint8_t> out = data.subspan(static_cast<std::size_t>(lo - dg0),
                                                       static_cast<std::size_t>(hi - lo));
      if (r.whole && lo == r.first && hi == r.end) {
        sms_[static_cast<unsigned>(r.target)].ecat_read_whole(out.data());
        whole_events(r);
        read_hit = true;
      } else if (r.target >= 0) {
        SmSignals sig;
        const auto n = static_cast<unsigned>(r.target);
        read_hit = sms_[n].read(Side::Ecat, static_cast<std::uint16_t>(paddr), out, sig) || read_hit;
        apply(n, sig);
      } else if (r.target == kRouteRam) {
        logical_detail::copy_bytes(out.data(), mem_.get() + paddr, out.size());
        read_hit = true;
      } else {
        read_hit = mem_read(static_cast<std::uint16_t>(paddr), out, Side::Ecat) || read_hit;
      }
    }
  }
  if (cmd != Command::Lrd) {
    // ESC write protection (0x0031) covers the RAM (Section I §13).
    const bool ram_protected = (mem_[reg::kEscWriteProtection] & bits::kWriteProtect) && !esc_write_enabled_;
    for (unsigned i = 0; i < route_writes_; ++i) {
      const FmmuRoute& r = write_routes_[i];
      const std::uint64_t lo = std::max(dg0, r.first);
      const std::uint64_t hi = std::min(dg1, r.end);
      if (lo >= hi) continue;
      const std::uint64_t paddr = r.physical + (lo - r.first);
      if (paddr >= kAddressSpace) continue;
      const std::span<const std::uint8_t> in = data.subspan(static_cast<std::size_t>(lo - dg0),
                                                            static_cast<std::size_t>(hi - lo));
      if (r.target == kRouteGeneral) {
        write_hit = mem_write(static_cast<std::uint16_t>(paddr), in, Side::Ecat) || write_hit;
      } else if (ram_protected) {
        // mem_write restarts the watchdog before it looks at the protection.
        if (r.target == kRouteRamWatchdog) restart_watchdog_over(r, paddr, in.size());
        continue;
      } else if (r.whole && lo == r.first && hi == r.end) {
        sms_[static_cast<unsigned>(r.target)].ecat_write_whole(in.data());
        whole_events(r);
        write_hit = true;
      } else if (r.target >= 0) {
        SmSignals sig;
        const auto n = static_cast<unsigned>(r.target);
        write_hit = sms_[n].write(Side::Ecat, static_cast<std::uint16_t>(paddr), in, sig) || write_hit;
        apply(n, sig);
      } else {  // plain RAM
        if (r.target == kRouteRamWatchdog) restart_watchdog_over(r, paddr, in.size());
        logical_detail::copy_bytes(mem_.get() + paddr, in.data(), in.size());
        write_hit = true;
      }
    }
  }
  return logical_detail::wkc_of(cmd, read_hit, write_hit);
}

}  // namespace ecat::esc
