// The datagram engine: what one ESC does to each datagram of a passing frame
// (ETG.1000.4 §5.4; Beckhoff ESC datasheet Section I §2.5 Tables 5 and 7;
// shared/spec/esc-registers.md §2). Addressing, data, ADP increment, WKC
// and the IRQ field. Logical commands go through the FMMUs (Section I §6).
#include <algorithm>
#include <array>
#include <bit>
#include <cstring>

#include "esc/esc.hpp"
#include "esc/registers.hpp"

namespace ecat::esc {

namespace {

// Scratch for one datagram's data (11-bit length), on the stack: no heap.
using Scratch = std::array<std::uint8_t, kFrameLengthMask + 1>;

constexpr std::uint16_t kWkcRead = 1;
constexpr std::uint16_t kWkcWrite = 1;
constexpr std::uint16_t kWkcReadWriteWrite = 2;  // the write part of an xRW

bool get_bit(const std::uint8_t* p, std::uint64_t bit) noexcept { return (p[bit / 8] >> (bit % 8)) & 1u; }
void put_bit(std::uint8_t* p, std::uint64_t bit, bool v) noexcept {
  const auto mask = static_cast<std::uint8_t>(1u << (bit % 8));
  p[bit / 8] = static_cast<std::uint8_t>(v ? (p[bit / 8] | mask) : (p[bit / 8] & ~mask));
}

}  // namespace

// The datagrams are walked in place (header read + jump); the timers run
// only when one is due (run_timers checks next_timer_).
bool Esc::process(const FrameView& frame, Nanoseconds now) noexcept {
  run_timers(now);
  now_ = now;  // the time of every access in this frame
  dc_.on_frame_arrival(0, now);
  // Circulating-frame prevention (Section I §3.5.1): a frame passing a
  // closed port 0 gets the circulating bit; if it already had it, the ESC
  // destroys the frame.
  if (!port_open_[0] && !frame.empty()) {
    if (frame.front().circulating()) return false;
    for (DatagramView d : frame) d.set_circulating(true);
  }
  register_write_enabled_ = false;
  esc_write_enabled_ = false;
  for (DatagramView d : frame) {
    process_datagram(d);
    const std::uint16_t irq = irq_field();
    if (irq != 0) d.set_irq(static_cast<std::uint16_t>(d.irq() | irq));
    if (reset_requested_) reset();
  }
  // Write-enable releases last for one frame only (Section I §13).
  register_write_enabled_ = false;
  esc_write_enabled_ = false;
  return true;
}

bool Esc::addressed_configured(std::uint16_t adp) const noexcept {
  if (adp == load_le<std::uint16_t>(mem_.get() + reg::kConfiguredStationAddress)) return true;
  return (dl_control() & bits::kDlStationAlias) != 0 &&
         adp == load_le<std::uint16_t>(mem_.get() + reg::kConfiguredStationAlias);
}

void Esc::process_datagram(DatagramView d) noexcept {
  const Command cmd = d.command();
  const Addressing mode = addressing(cmd);
  if (mode == Addressing::None) return;
  if (mode == Addressing::Logical) {
    if (cmd == Command::Lrw && !config_.lrw) return;  // 0x0008 bit 9: passes untouched
    d.add_wkc(process_logical(d));
    return;
  }
  const std::uint16_t adp = d.adp();
  if (increments_adp(cmd)) d.set_adp(static_cast<std::uint16_t>(adp + 1));
  if (is_read_write(cmd) && !config_.read_write_commands) return;  // 0x0008 bit 10
  bool addressed = true;
  if (mode == Addressing::AutoIncrement) addressed = adp == 0;
  if (mode == Addressing::Configured) addressed = addressed_configured(adp);
  const std::uint16_t ado = d.ado();
  Bytes data = d.data();
  // xRMW: read on the addressed slave, write on every other (Section I Table 7).
  if (cmd == Command::Armw || cmd == Command::Frmw) {
    const bool ok = addressed ? mem_read(ado, data, Side::Ecat) : mem_write(ado, data, Side::Ecat);
    if (ok) d.add_wkc(kWkcRead);
    return;
  }
  if (!addressed) return;
  const bool broadcast = mode == Addressing::Broadcast;
  std::uint16_t wkc = 0;
  if (is_read_write(cmd)) {
    // Read first (data returned is the memory before the write), then write
    // the incoming data.
    Scratch incoming;
    std::memcpy(incoming.data(), data.data(), data.size());
    Scratch result;
    std::memset(result.data(), 0, data.size());
    if (mem_read(ado, std::span(result.data(), data.size()), Side::Ecat)) {
      wkc = static_cast<std::uint16_t>(wkc + kWkcRead);
      for (std::size_t i = 0; i < data.size(); ++i) {
        data[i] = broadcast ? static_cast<std::uint8_t>(data[i] | result[i]) : result[i];
      }
    }
    if (mem_write(ado, std::span<const std::uint8_t>(incoming.data(), data.size()), Side::Ecat)) {
      wkc = static_cast<std::uint16_t>(wkc + kWkcReadWriteWrite);
    }
  } else if (reads(cmd)) {
    if (broadcast) {
      // BRD: the data of all slaves ORed together.
      Scratch result;
      std::memset(result.data(), 0, data.size());
      if (mem_read(ado, std::span(result.data(), data.size()), Side::Ecat)) {
        wkc = kWkcRead;
        for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<std::uint8_t>(data[i] | result[i]);
      }
    } else if (mem_read(ado, data, Side::Ecat)) {
      wkc = kWkcRead;
    }
  } else if (writes(cmd)) {
    if (mem_write(ado, data, Side::Ecat)) wkc = kWkcWrite;
  }
  d.add_wkc(wkc);
}

// Logical addressing through every active FMMU (Section I §6; ETG.1000.4
// §5.4.3): +1 if any read FMMU hit accessible memory, +1 (LWR) / +2 (LRW)
// if any write FMMU did, whatever the number of FMMUs involved. The cost
// follows the bytes this ESC maps, never the datagram length.
std::uint16_t Esc::process_logical(DatagramView d) noexcept {
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
  Scratch incoming;
  const std::uint8_t* wsrc = data.data();
  std::size_t origin = 0;
  if (cmd == Command::Lrw && wlo < whi && rlo < whi && wlo < rhi) {
    std::memcpy(incoming.data(), data.data() + wlo, whi - wlo);
    wsrc = incoming.data();
    origin = wlo;
  }
  bool read_hit = false;
  bool write_hit = false;
  Scratch phys;
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
  std::uint16_t wkc = 0;
  if (read_hit) wkc = static_cast<std::uint16_t>(wkc + kWkcRead);
  if (write_hit) wkc = static_cast<std::uint16_t>(wkc + (cmd == Command::Lrw ? kWkcReadWriteWrite : kWkcWrite));
  return wkc;
}

}  // namespace ecat::esc
