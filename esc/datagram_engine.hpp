// The datagram engine: what one ESC does to each datagram of a passing frame
// (ETG.1000.4 §5.4; Beckhoff ESC datasheet Section I §2.5 Tables 5 and 7;
// shared/spec/esc-registers.md §2). Addressing, data, ADP increment, WKC
// and the IRQ field. Logical commands go through the FMMUs (Section I §6;
// esc/logical_access.hpp).
//
// Inline in this internal header (issue 8): esc::Segment includes it, so the
// whole pass of a frame through an ESC compiles into the segment's loop
// with no call per ESC. Only esc/segment.cpp and esc/datagram_engine.cpp
// include it; everything else calls Esc::process.
#pragma once

#include <array>
#include <cstring>

#include "esc/datagram_rules.hpp"
#include "esc/dc/dc_registers.hpp"
#include "esc/esc.hpp"
#include "esc/logical_access.hpp"
#include "esc/register_map.hpp"
#include "esc/registers.hpp"
#include "esc/small_copy.hpp"

namespace ecat::esc {

namespace engine_detail {

// What each command code does (ETG.1000.4 §5.4, Table 5), looked up once per
// datagram instead of several switches. Codes are <= kLastCommand in a
// validated frame.
struct CommandTraits {
  Addressing mode = Addressing::None;
  bool increments_adp = false;
  bool read_write = false;
  bool rmw = false;  // ARMW/FRMW
  bool reads = false;
  bool writes = false;
};

inline constexpr std::array<CommandTraits, kLastCommand + 1> kCommandTraits = [] {
  std::array<CommandTraits, kLastCommand + 1> t{};
  for (std::uint8_t code = 0; code <= kLastCommand; ++code) {
    const auto c = static_cast<Command>(code);
    t[code] = CommandTraits{addressing(c), increments_adp(c), is_read_write(c),
                            c == Command::Armw || c == Command::Frmw, reads(c), writes(c)};
  }
  return t;
}();

}  // namespace engine_detail

// The datagrams are walked in place (header read + jump); the timers run
// only when one is due (run_timers checks next_timer_). `count` >= 1.
[[gnu::always_inline]] inline bool Esc::process_datagrams(DatagramView first, std::size_t count,
                                                          Nanoseconds now) noexcept {
  run_timers(now);
  now_ = now;  // the time of every access in this frame
  dc_.on_frame_arrival(0, now);
  // Circulating-frame prevention (Section I §3.5.1): a frame passing a
  // closed port 0 gets the circulating bit; if it already had it, the ESC
  // destroys the frame.
  if (!port_open_[0]) [[unlikely]] {
    if (first.circulating()) return false;
    DatagramView c = first;
    for (std::size_t left = count;;) {
      c.set_circulating(true);
      if (--left == 0) break;
      c = c.next();
    }
  }
  // The write-enable releases are false here: only ECAT writes of a frame
  // set them, and every pass clears them at its end (and reset()).
  DatagramView d = first;
  for (std::size_t left = count;;) {
    process_datagram(d);
    const std::uint16_t irq = irq_field();
    if (irq != 0) d.set_irq(static_cast<std::uint16_t>(d.irq() | irq));
    if (reset_requested_) [[unlikely]] reset();
    if (--left == 0) break;
    d = d.next();
  }
  // Write-enable releases last for one frame only (Section I §13).
  register_write_enabled_ = false;
  esc_write_enabled_ = false;
  return true;
}

// The station alias is compared first (it sits next to the station address)
// and its enable bit in DL control only on a match: the same result, one
// register line fewer for the ESCs a datagram passes by.
inline bool Esc::addressed_configured(std::uint16_t adp) const noexcept {
  const std::uint8_t* m = mem_.get();
  if (adp == load_le<std::uint16_t>(m + reg::kConfiguredStationAddress)) return true;
  return adp == load_le<std::uint16_t>(m + reg::kConfiguredStationAlias) &&
         (m[reg::kDlControl + 3] & (bits::kDlStationAlias >> 24)) != 0;
}

// An ECAT read of register bytes outside the DC block (the usual FPRD/APRD
// of a status register): one copy, then the bytes whose read has an effect
// (esc/register_map.hpp), in address order as in reg_read. The hot one, AL
// status 0x0130, only acknowledges ECAT event request bit 3 (Section II
// 0x0130/0x0210) and is handled directly; the others by their per-byte
// handler. Anything else goes through mem_read.
[[gnu::always_inline]] inline bool Esc::ecat_read(std::uint16_t address, Bytes out) noexcept {
  const std::size_t n = out.size();
  const std::uint32_t end = address + static_cast<std::uint32_t>(n);
  if (!config_.fast_paths || n == 0 || end > reg::kProcessRam || (end > reg::kDcBase && address < reg::kDcEnd)) {
    return mem_read(address, out, Side::Ecat);
  }
  copy_small(out.data(), mem_.get() + address, n);
  constexpr std::size_t kScanBytes = 16;  // longer reads check the 16-byte blocks first
  if (n > kScanBytes && !register_map::any_in(address, n, register_map::kReadEffectEcat)) return true;
  const std::uint8_t* flags = register_map::kTable.byte.data() + address;
  for (std::size_t i = 0; i < n; ++i) {
    if ((flags[i] & register_map::kReadEffectEcat) == 0) continue;
    const auto a = static_cast<std::uint16_t>(address + i);
    if (a == reg::kAlStatus) {
      clear_ecat_event(bits::kEcatEventAlStatus);  // the stored byte is what is read
    } else {
      out[i] = reg_read_byte(a, Side::Ecat);
    }
  }
  return true;
}

// The system time of every DC cycle (ETG.1020 §22; SOEM's FRMW of the
// reference clock, IgH's ARMW/FRMW), addressing done: the addressed ESC
// reads 0x0910, every other one writes it into its time loop unless write
// protection is on, WKC + 1 - what ecat_read/mem_write do with it, without
// mem_read/reg_read or mem_write/reg_write's range tests. False (nothing
// done) for the general path: other lengths or addresses, no DC, a
// watchdog-only SM (its restart is mem_write's), fast_paths off. Out of
// line: inlined into the frame pass, it cost the one-ESC FPRD 17
// instructions.
[[gnu::noinline]] inline bool Esc::system_time_rmw(DatagramView d, bool addressed) noexcept {
  constexpr std::size_t kSystemTimeBytes = 8;
  constexpr std::size_t kSystemTimeLowBytes = 4;
  const std::size_t n = d.length();
  if (d.ado() != reg::kDcBase + dcreg::kSystemTime || (n != kSystemTimeBytes && n != kSystemTimeLowBytes) ||
      !config_.fast_paths || !config_.dc || sm_watchdog_only_ != 0) {
    return false;
  }
  Bytes data = d.data();
  if (addressed) {
    dc_.read(dcreg::kSystemTime, data, now_, Side::Ecat);
  } else {
    if (write_protection_active()) return true;
    dc_.write_system_time(data, now_);
  }
  d.add_wkc(kWkcRead);
  return true;
}

// The commands of a cyclic frame (FPRD/FPWR, APRD/APWR, LRD/LWR/LRW, BWR)
// each have their own case; the others share the table-driven general one.
[[gnu::always_inline]] inline void Esc::process_datagram(DatagramView d) noexcept {
  const Command cmd = d.command();
  switch (cmd) {
    case Command::Fprd:
    case Command::Fpwr: {
      if (!addressed_configured(d.adp())) return;
      Bytes data = d.data();
      const bool hit = cmd == Command::Fprd ? ecat_read(d.ado(), data) : mem_write(d.ado(), data, Side::Ecat);
      if (hit) d.add_wkc(cmd == Command::Fprd ? kWkcRead : kWkcWrite);
      return;
    }
    case Command::Aprd:
    case Command::Apwr: {
      const std::uint16_t adp = d.adp();
      d.set_adp(static_cast<std::uint16_t>(adp + 1));
      if (adp != 0) return;
      Bytes data = d.data();
      const bool hit = cmd == Command::Aprd ? ecat_read(d.ado(), data) : mem_write(d.ado(), data, Side::Ecat);
      if (hit) d.add_wkc(cmd == Command::Aprd ? kWkcRead : kWkcWrite);
      return;
    }
    case Command::Brd: {
      constexpr std::size_t kAlStatusBytes = 2;
      if (d.ado() != reg::kAlStatus || d.length() != kAlStatusBytes || !config_.fast_paths) break;
      // The AL status poll of every cycle (SOEM's ecx_readstate, IgH's
      // state check): what the general path does for these two bytes -
      // ADP + 1, 0x0130 acknowledges ECAT event bit 3, 0x0131 is read as
      // stored (esc/register_map.hpp) - without its checks and loops.
      d.set_adp(static_cast<std::uint16_t>(d.adp() + 1));
      const std::uint8_t* m = mem_.get() + reg::kAlStatus;
      std::uint8_t* out = d.data().data();
      out[0] = static_cast<std::uint8_t>(out[0] | m[0]);
      out[1] = static_cast<std::uint8_t>(out[1] | m[1]);
      clear_ecat_event(bits::kEcatEventAlStatus);
      d.add_wkc(kWkcRead);
      return;
    }
    case Command::Lrd:
    case Command::Lwr:
    case Command::Lrw: {
      const std::uint16_t wkc = process_logical(d);
      if (wkc != 0) d.add_wkc(wkc);
      return;
    }
    default:
      break;
  }
  const engine_detail::CommandTraits& traits = engine_detail::kCommandTraits[static_cast<std::uint8_t>(cmd)];
  const Addressing mode = traits.mode;
  if (mode == Addressing::None) return;
  const std::uint16_t adp = d.adp();
  if (traits.increments_adp) d.set_adp(static_cast<std::uint16_t>(adp + 1));
  if (traits.read_write && !config_.read_write_commands) return;  // 0x0008 bit 10
  bool addressed = true;
  if (mode == Addressing::AutoIncrement) addressed = adp == 0;
  if (mode == Addressing::Configured) addressed = addressed_configured(adp);
  if (!addressed && !traits.rmw) return;
  process_addressed(d, traits, addressed, mode == Addressing::Broadcast);
}

// The datagram addresses this ESC (or is an xRMW it writes). xRW and BRD
// merge the data with a scratch copy: out of line (process_merged).
[[gnu::always_inline]] inline void Esc::process_addressed(DatagramView d, const engine_detail::CommandTraits& traits,
                                                          bool addressed, bool broadcast) noexcept {
  const std::uint16_t ado = d.ado();
  Bytes data = d.data();
  // xRMW: read on the addressed slave, write on every other (Section I Table 7).
  if (traits.rmw) {
    if (system_time_rmw(d, addressed)) return;
    const bool ok = addressed ? ecat_read(ado, data) : mem_write(ado, data, Side::Ecat);
    if (ok) d.add_wkc(kWkcRead);
    return;
  }
  if (traits.read_write || (traits.reads && broadcast)) {
    constexpr std::size_t kShortBrd = 8;
    if (!traits.read_write && data.size() <= kShortBrd) {
      // A short BRD (the AL status poll of every cycle): each ESC ORs its
      // bytes in through the inline ECAT read, no scratch copy.
      std::array<std::uint8_t, kShortBrd> result{};
      if (ecat_read(ado, Bytes(result.data(), data.size()))) {
        for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<std::uint8_t>(data[i] | result[i]);
        d.add_wkc(kWkcRead);
      }
      return;
    }
    process_merged(d, traits.read_write, broadcast);
    return;
  }
  std::uint16_t wkc = 0;
  if (traits.reads) {
    if (ecat_read(ado, data)) wkc = kWkcRead;
  } else if (traits.writes) {
    if (mem_write(ado, data, Side::Ecat)) wkc = kWkcWrite;
  }
  d.add_wkc(wkc);
}

}  // namespace ecat::esc
