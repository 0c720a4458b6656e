// Logical addressing through the FMMUs (ESC datasheet Section I §6;
// ETG.1000.4 §5.4.3): +1 to the WKC if any read FMMU hit accessible memory,
// +1 (LWR) / +2 (LRW) if any write FMMU did, whatever the number of FMMUs
// involved. The cost follows the bytes this ESC maps, never the datagram
// length: the FMMUs are decoded and routed when their registers (or the
// SMs) change, so a frame only compares ranges and copies mapped bytes.
#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <tuple>
#include <utility>

#include "esc/datagram_rules.hpp"
#include "esc/esc.hpp"
#include "esc/logical_access.hpp"
#include "esc/registers.hpp"

namespace ecat::esc {

namespace {

bool get_bit(const std::uint8_t* p, std::uint64_t bit) noexcept { return (p[bit / 8] >> (bit % 8)) & 1u; }
void put_bit(std::uint8_t* p, std::uint64_t bit, bool v) noexcept {
  const auto mask = static_cast<std::uint8_t>(1u << (bit % 8));
  p[bit / 8] = static_cast<std::uint8_t>(v ? (p[bit / 8] | mask) : (p[bit / 8] & ~mask));
}

}  // namespace

// The routed path needs every active FMMU whole bytes on both sides and no
// logical byte both read and written by this ESC (an LRW could otherwise
// read over data it still has to write). For each FMMU, where its physical
// range goes: one SM (the lowest-numbered enabled SM overlapping the range
// covers all of it), plain RAM (no enabled SM overlaps it), or mem_read/
// mem_write - exactly what those would find byte by byte.
void Esc::update_fmmus() noexcept {
  ++fmmu_epoch_;
  fmmu_active_ = 0;
  route_reads_ = 0;
  route_writes_ = 0;
  fmmus_routed_ = config_.fast_paths;  // off: every LRD/LWR/LRW takes the general path
  logical_first_ = 0;
  logical_end_ = 0;
  for (unsigned k = 0; k < config_.fmmu_count; ++k) {
    const Fmmu& f = fmmus_[k];
    if (!f.active()) continue;
    fmmu_active_ |= 1u << k;
    if (!f.byte_aligned()) fmmus_routed_ = false;
    FmmuRoute r{f.logical_start, std::uint64_t{f.logical_start} + f.length, f.physical_start, kRouteGeneral};
    if (logical_first_ == logical_end_) {
      logical_first_ = r.first;
      logical_end_ = r.end;
    } else {
      logical_first_ = std::min(logical_first_, r.first);
      logical_end_ = std::max(logical_end_, r.end);
    }
    const std::uint32_t p1 = r.physical + f.length;
    if (r.physical >= reg::kProcessRam && p1 <= ram_end()) {
      r.target = kRouteRam;
      for (std::uint32_t left = sm_enabled_; left != 0; left &= left - 1) {
        const auto n = static_cast<unsigned>(std::countr_zero(left));
        const std::uint32_t s0 = sms_[n].start();
        const std::uint32_t s1 = sms_[n].end();
        if (s1 <= r.physical || s0 >= p1) continue;  // no overlap
        r.target = s0 <= r.physical && p1 <= s1 ? static_cast<std::int8_t>(n) : kRouteGeneral;
        break;
      }
    }
    if (f.read) routes_[route_reads_++] = whole_route(r, f.length, false);
    if (f.write) {
      // A write over the byte of a 1-byte SM (watchdog trigger only,
      // Section II 0x0802) restarts the watchdog as mem_write would.
      FmmuRoute w = r;
      if (w.target == kRouteRam && touches_watchdog_only_sm(w.physical, p1)) {
        w.target = kRouteRamWatchdog;
        std::tie(w.watchdog_first, w.watchdog_end) = watchdog_only_sm_over(w.physical, p1);
      }
      write_routes_[route_writes_++] = whole_route(w, f.length, true);
    }
  }
  for (unsigned a = 0; a < route_reads_; ++a) {
    for (unsigned b = 0; b < route_writes_; ++b) {
      const FmmuRoute& rd = routes_[a];
      const FmmuRoute& wr = write_routes_[b];
      if (rd.first < wr.end && wr.first < rd.end) fmmus_routed_ = false;
    }
  }
}

// An ECAT write of `size` bytes at `address` restarts the process-data
// watchdog when it reaches the byte of a watchdog-only SM (Section II
// 0x0802): mem_write's rule, and the plain-RAM routes'. Out of line: the
// frame pass that inlines the routes keeps its size for the devices
// without such an SM.
void Esc::restart_watchdog_over(std::uint64_t address, std::size_t size) noexcept {
  const auto first = static_cast<std::uint32_t>(address);
  if (touches_watchdog_only_sm(first, first + static_cast<std::uint32_t>(size))) restart_process_data_watchdog();
}

// The same for a plain-RAM route's write, from the SM bytes the route keeps
// (update_fmmus): the frame reads no SM.
void Esc::restart_watchdog_over(const FmmuRoute& r, std::uint64_t address, std::size_t size) noexcept {
  if (r.watchdog_end == 0) {
    restart_watchdog_over(address, size);
  } else if (address < r.watchdog_end && r.watchdog_first < address + size) {
    restart_process_data_watchdog();
  }
}

std::pair<std::uint32_t, std::uint32_t> Esc::watchdog_only_sm_over(std::uint32_t first,
                                                                   std::uint32_t end) const noexcept {
  std::pair<std::uint32_t, std::uint32_t> found{0, 0};
  for (std::uint32_t left = sm_watchdog_only_; left != 0; left &= left - 1) {
    const SyncManager& sm = sms_[static_cast<unsigned>(std::countr_zero(left))];
    const std::uint32_t at = sm.start();
    const std::uint32_t sm_end = at + std::max<std::uint32_t>(sm.length(), 1);
    if (at >= end || first >= sm_end) continue;
    if (found.second != 0) return {0, 0};  // several
    found = {at, sm_end};
  }
  return found;
}

// A route to SM n that maps exactly its buffer area, read (ecat_write =
// false) or written by ECAT as that SM allows, is taken whole in one step;
// its events are what SyncManager::read/write would signal for an access
// that is both the first and the last byte: the ECAT event acknowledged,
// the AL event if control bit 5, the watchdog restart (write) if bit 6.
Esc::FmmuRoute Esc::whole_route(FmmuRoute r, std::uint32_t length, bool ecat_write) const noexcept {
  if (r.target < 0) return r;
  const auto n = static_cast<unsigned>(r.target);
  const SyncManager& sm = sms_[n];
  if (r.physical != sm.start() || length != sm.length() || !sm.whole_ecat_ready(ecat_write)) return r;
  r.whole = true;
  r.watchdog = ecat_write && (sm.control() & sm_bits::kWatchdogTrigger) != 0;
  r.ecat_clear = static_cast<std::uint16_t>(n < bits::kEcatEventSmCount ? 1u << (bits::kEcatEventSmShift + n) : 0u);
  r.al_raise = (sm.control() & sm_bits::kAlEventEnable) != 0 ? 1u << (bits::kAlEventSmShift + n) : 0;
  return r;
}

// The general path: bit-granular FMMUs, through the SM rules of mem_read /
// mem_write. Only mapped bits change in the frame (read) or in memory (write).
std::uint16_t Esc::process_logical_bits(DatagramView d) noexcept {
  const Command cmd = d.command();
  Bytes data = d.data();
  if (data.empty()) return 0;
  const std::uint64_t dg_first = static_cast<std::uint64_t>(d.logical_address()) * 8;
  const std::uint64_t dg_last = dg_first + data.size() * 8 - 1;
  // Which FMMUs overlap the datagram, and where (bit numbers).
  struct Hit {
    const Fmmu* fmmu;
    std::uint64_t lo;
    std::uint64_t hi;
  };
  std::array<Hit, kMaxFmmus> hits;
  std::size_t count = 0;
  std::size_t wlo = data.size();  // byte range of the datagram the write FMMUs take
  std::size_t whi = 0;
  std::size_t rlo = data.size();  // ... and the read FMMUs
  std::size_t rhi = 0;
  for (std::uint32_t left = fmmu_active_; left != 0; left &= left - 1) {
    const Fmmu& f = fmmus_[static_cast<unsigned>(std::countr_zero(left))];
    const std::uint64_t lo = std::max(dg_first, f.first_bit());
    const std::uint64_t hi = std::min(dg_last, f.last_bit());
    if (lo > hi) continue;
    hits[count++] = Hit{&f, lo, hi};
    const auto first = static_cast<std::size_t>((lo - dg_first) / 8);
    const auto end = static_cast<std::size_t>((hi - dg_first) / 8) + 1;
    if (f.write) {
      wlo = std::min(wlo, first);
      whi = std::max(whi, end);
    }
    if (f.read) {
      rlo = std::min(rlo, first);
      rhi = std::max(rhi, end);
    }
  }
  if (count == 0) return 0;
  // LRW writes the data as it arrived while reads replace it: keep the
  // bytes the writes need when a read lands on them. `wsrc[i - origin]` is
  // incoming byte i.
  DatagramScratch incoming;
  const std::uint8_t* wsrc = data.data();
  std::size_t origin = 0;
  if (cmd == Command::Lrw && wlo < whi && rlo < whi && wlo < rhi) {
    std::memcpy(incoming.data(), data.data() + wlo, whi - wlo);
    wsrc = incoming.data();
    origin = wlo;
  }
  bool read_hit = false;
  bool write_hit = false;
  DatagramScratch phys;
  // Two passes: all reads, then all writes, so a byte read and written by
  // the same LRW returns its old value.
  for (int pass = 0; pass < 2; ++pass) {
    const bool reading = pass == 0;
    if (reading ? !reads(cmd) : !writes(cmd)) continue;
    for (std::size_t h = 0; h < count; ++h) {
      const Fmmu& f = *hits[h].fmmu;
      if (reading ? !f.read : !f.write) continue;
      const std::uint64_t lo = hits[h].lo;
      const std::uint64_t bits_n = hits[h].hi - lo + 1;
      const std::uint64_t pbit = static_cast<std::uint64_t>(f.physical_start) * 8 + f.physical_start_bit +
                                 (lo - f.first_bit());
      const std::uint64_t pbyte = pbit / 8;
      if (pbyte >= kAddressSpace) continue;
      const auto paddr = static_cast<std::uint16_t>(pbyte);
      const std::size_t doff = static_cast<std::size_t>((lo - dg_first) / 8);
      if ((lo % 8) == 0 && (pbit % 8) == 0 && (bits_n % 8) == 0) {
        // Whole bytes on both sides: straight through the SM rules.
        const std::size_t n = static_cast<std::size_t>(bits_n / 8);
        if (reading) {
          read_hit = mem_read(paddr, data.subspan(doff, n), Side::Ecat) || read_hit;
        } else {
          write_hit = mem_write(paddr, std::span<const std::uint8_t>(wsrc + (doff - origin), n), Side::Ecat) ||
                      write_hit;
        }
        continue;
      }
      // Bit-granular: only mapped bits change in the frame (read) or in
      // memory (write; unmapped bits of touched bytes keep their value).
      const std::size_t pbytes = static_cast<std::size_t>((pbit + bits_n - 1) / 8 - pbyte + 1);
      std::span<std::uint8_t> buf(phys.data(), pbytes);
      const std::uint64_t pshift = pbit - pbyte * 8;
      const std::uint64_t dshift = lo - dg_first;
      if (reading) {
        std::memset(buf.data(), 0, buf.size());
        if (!mem_read(paddr, buf, Side::Ecat)) continue;
        read_hit = true;
        for (std::uint64_t b = 0; b < bits_n; ++b) put_bit(data.data(), dshift + b, get_bit(buf.data(), pshift + b));
      } else {
        peek(paddr, buf);
        const std::uint64_t sshift = dshift - origin * 8;
        for (std::uint64_t b = 0; b < bits_n; ++b) put_bit(buf.data(), pshift + b, get_bit(wsrc, sshift + b));
        write_hit = mem_write(paddr, buf, Side::Ecat) || write_hit;
      }
    }
  }
  return logical_detail::wkc_of(cmd, read_hit, write_hit);
}

}  // namespace ecat::esc
