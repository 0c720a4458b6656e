// One SyncManager: consistent, protected access to a buffer in process RAM
// shared by the EtherCAT side and the PDI (ESC datasheet Section I §8,
// Section II 0x0800+8n; ETG.1000.4 §6.7; shared/spec/esc-registers.md §7).
// Mailbox (1-buffer) and buffered (3-buffer) modes, direction, activation,
// PDI deactivation, status byte and the interrupt bits. The register bytes
// live in the ESC memory; this object keeps the buffer state behind them.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <span>

#include "common/le.hpp"
#include "esc/access_side.hpp"
#include "esc/registers.hpp"

namespace ecat::esc {

namespace sm_bits {
// Control byte (offset 4).
inline constexpr std::uint8_t kModeMask = 0x03;
inline constexpr std::uint8_t kModeBuffered = 0x00;
inline constexpr std::uint8_t kModeMailbox = 0x02;
inline constexpr std::uint8_t kDirectionMask = 0x0C;
inline constexpr std::uint8_t kDirectionRead = 0x00;   // ECAT reads, PDI writes
inline constexpr std::uint8_t kDirectionWrite = 0x04;  // ECAT writes, PDI reads
inline constexpr std::uint8_t kEcatEventEnable = 0x10;
inline constexpr std::uint8_t kAlEventEnable = 0x20;
inline constexpr std::uint8_t kWatchdogTrigger = 0x40;
// Status byte (offset 5).
inline constexpr std::uint8_t kStatusWriteEvent = 0x01;
inline constexpr std::uint8_t kStatusReadEvent = 0x02;
inline constexpr std::uint8_t kStatusMailboxFull = 0x08;
inline constexpr unsigned kStatusBufferShift = 4;
inline constexpr std::uint8_t kStatusBufferMask = 0x30;
inline constexpr std::uint8_t kStatusReadBufferOpen = 0x40;
inline constexpr std::uint8_t kStatusWriteBufferOpen = 0x80;
// Activate byte (offset 6).
inline constexpr std::uint8_t kActivateEnable = 0x01;
inline constexpr std::uint8_t kActivateRepeat = 0x02;
inline constexpr std::uint8_t kActivateWritable = 0xC3;  // bits 0, 1, 6, 7
// PDI control byte (offset 7).
inline constexpr std::uint8_t kPdiDeactivate = 0x01;
inline constexpr std::uint8_t kPdiRepeatAck = 0x02;
inline constexpr std::uint8_t kPdiControlWritable = 0x03;
inline constexpr std::uint8_t kNoBufferWritten = 3;  // status bits 5:4 before the first write
inline constexpr std::uint16_t kMinActiveLength = 2;
inline constexpr std::uint16_t kWatchdogOnlyLength = 1;  // 0x0802 = 1: watchdog trigger only
}  // namespace sm_bits

// What an access did that the ESC must turn into event register bits.
struct SmSignals {
  bool raise_al = false;        // AL event request bit 8+n (PDI to be told)
  bool clear_al = false;
  bool raise_ecat = false;      // ECAT event request SM bit (master to be told)
  bool clear_ecat = false;
  bool watchdog_trigger = false;  // restart the process-data watchdog
};

class SyncManager {
 public:
  // `regs` = the SM's 8 register bytes inside ESC memory; `memory` = the
  // whole 64 KiB ESC memory (buffers are redirected inside it).
  void bind(std::uint8_t* regs, std::uint8_t* memory, std::uint32_t memory_end) noexcept;
  // Called after any register byte changed (ECAT write of 0..6, PDI write of 7).
  void on_register_written(unsigned offset, std::uint8_t old_value) noexcept;
  void reset_state() noexcept;

  std::uint16_t start() const noexcept { return load_le<std::uint16_t>(regs_ + reg::sm::kStartAddress); }
  std::uint16_t length() const noexcept { return load_le<std::uint16_t>(regs_ + reg::sm::kLength); }
  std::uint8_t control() const noexcept { return regs_[reg::sm::kControl]; }
  bool mailbox() const noexcept { return (control() & sm_bits::kModeMask) == sm_bits::kModeMailbox; }
  // True for master->slave buffers (ECAT writes, PDI reads).
  bool ecat_writes() const noexcept {
    return (control() & sm_bits::kDirectionMask) == sm_bits::kDirectionWrite;
  }
  // Enabled by ECAT (0x0806 bit 0), length >= 2: guards its buffer area.
  bool enabled() const noexcept {
    return (regs_[reg::sm::kActivate] & sm_bits::kActivateEnable) != 0 && length() >= sm_bits::kMinActiveLength;
  }
  // ESC datasheet Section II 0x0802: "shall be greater 1, otherwise SyncManager
  // is not activated. If set to 1, only Watchdog Trigger is generated if
  // available". Enabled with length 1, ECAT writes its byte and control bit 6
  // is set: the byte stays plain RAM, but an ECAT write to it restarts the
  // process-data watchdog (e.g. a device with one byte of outputs).
  bool watchdog_trigger_only() const noexcept {
    return (regs_[reg::sm::kActivate] & sm_bits::kActivateEnable) != 0 && length() == sm_bits::kWatchdogOnlyLength &&
           ecat_writes() && (control() & sm_bits::kWatchdogTrigger) != 0;
  }
  // An SM over registers (below the process RAM at 1000h: the digital
  // output data 0F00h-0F03h of an EL9800 revision, SM0 4 bytes, control
  // 46h) holds no buffer there - the bytes are the registers - but an ECAT
  // write to them restarts the process-data watchdog when control bit 6 is
  // set (Section II 0x0F00 "Digital I/O output data", 0x0804 bit 6).
  bool watchdog_trigger_on_registers() const noexcept {
    return (regs_[reg::sm::kActivate] & sm_bits::kActivateEnable) != 0 && length() > 0 &&
           start() < reg::kProcessRam && ecat_writes() && (control() & sm_bits::kWatchdogTrigger) != 0;
  }
  bool pdi_deactivated() const noexcept { return (regs_[reg::sm::kPdiControl] & sm_bits::kPdiDeactivate) != 0; }
  bool covers(std::uint32_t address) const noexcept { return enabled() && address >= start() && address < end(); }
  std::uint32_t end() const noexcept { return static_cast<std::uint32_t>(start()) + length(); }
  bool mailbox_full() const noexcept { return full_; }

  // An access to [address, address + data.size()) that lies fully inside
  // this SM's area, from `side`. Copies the data if allowed (redirecting to
  // the current 3-buffer). Returns true if carried out.
  bool read(Side side, std::uint16_t address, std::span<std::uint8_t> out, SmSignals& sig) noexcept;
  bool write(Side side, std::uint16_t address, std::span<const std::uint8_t> in, SmSignals& sig) noexcept;
  // The same as read()/write() from the ECAT side of the whole buffer
  // [start(), end()) in one access, for an SM that is enabled, buffered,
  // not PDI-deactivated, read (write) by ECAT and whose three buffers end
  // inside ESC memory: what Esc::update_fmmus checked when it routed an
  // FMMU here. The caller raises the events (ECAT event acknowledged, AL
  // event if control bit 5, and for a write the watchdog if bit 6).
  void ecat_read_whole(std::uint8_t* out) noexcept;
  void ecat_write_whole(const std::uint8_t* in) noexcept;
  // Whether the whole-buffer access above may be used for this SM by ECAT.
  bool whole_ecat_ready(bool ecat_write) const noexcept {
    return enabled() && !mailbox() && !pdi_deactivated() && ecat_writes() == ecat_write &&
           end() + 2u * length() <= mem_end_;
  }

  // The buffered-mode (3-buffer) part of read()/write() without the copy
  // (issue 8: Esc's whole-buffer PDI access in place). When buffered(side,
  // write) holds, read()/write() of `n` > 0 bytes at `address` would take
  // the buffered branch; buffered_read/buffered_write apply exactly its
  // rules (buffer selection or exchange, status byte, signals) and return
  // where the bytes are (read) or go (write, the buffer before the
  // exchange): physical address in ESC memory, to be clipped at
  // memory_end() as copy_out/copy_in do. write_position() is that place for
  // the next write, without side effects.
  bool buffered(Side side, bool write) const noexcept {
    return !pdi_deactivated() && !mailbox() && writer(side) == write;
  }
  std::uint32_t buffered_read(Side side, std::uint16_t address, std::size_t n, SmSignals& sig) noexcept;
  std::uint32_t buffered_write(Side side, std::uint16_t address, std::size_t n, SmSignals& sig) noexcept;
  std::uint32_t write_position(std::uint16_t address) const noexcept { return physical(write_buffer_, address); }
  std::uint32_t memory_end() const noexcept { return mem_end_; }

 private:
  bool writer(Side side) const noexcept { return (side == Side::Ecat) == ecat_writes(); }
  std::uint32_t physical(std::uint8_t buffer, std::uint16_t address) const noexcept;
  void set_status_bits(std::uint8_t set, std::uint8_t clear) noexcept;

  std::uint8_t* regs_ = nullptr;
  std::uint8_t* mem_ = nullptr;
  std::uint32_t mem_end_ = 0;
  // Mailbox state.
  bool full_ = false;
  // 3-buffer state (Section I §8.1): buffer the reader uses, the latest
  // completely written one, the one the writer fills.
  std::uint8_t read_buffer_ = 0;
  std::uint8_t latest_ = sm_bits::kNoBufferWritten;
  std::uint8_t write_buffer_ = 1;
  bool read_open_ = false;
  bool write_open_ = false;
};

// The buffer rules below are inline: they run for every SM access of a
// frame (issue 8), and inlined into the FMMU route they cost no call.
inline std::uint32_t SyncManager::physical(std::uint8_t buffer, std::uint16_t address) const noexcept {
  return static_cast<std::uint32_t>(address) + static_cast<std::uint32_t>(buffer) * length();
}

inline void SyncManager::set_status_bits(std::uint8_t set, std::uint8_t clear) noexcept {
  regs_[reg::sm::kStatus] = static_cast<std::uint8_t>((regs_[reg::sm::kStatus] & ~clear) | set);
}

namespace sm_detail {
inline constexpr unsigned kBufferIndexSum = 0 + 1 + 2;  // the three buffers of buffered mode

// Copies, clipped at the end of ESC memory (bytes past it read as 0 / are dropped).
inline void copy_out(const std::uint8_t* mem, std::uint32_t mem_end, std::uint32_t at, std::span<std::uint8_t> out) {
  std::size_t n = at >= mem_end ? 0 : std::min<std::size_t>(out.size(), mem_end - at);
  if (n) std::memcpy(out.data(), mem + at, n);
  if (n < out.size()) std::memset(out.data() + n, 0, out.size() - n);
}
inline void copy_in(std::uint8_t* mem, std::uint32_t mem_end, std::uint32_t at, std::span<const std::uint8_t> in) {
  std::size_t n = at >= mem_end ? 0 : std::min<std::size_t>(in.size(), mem_end - at);
  if (n) std::memcpy(mem + at, in.data(), n);
}

// The interrupt for the other side, when `side` completed a buffer.
inline void signal_other_side(Side side, std::uint8_t control, SmSignals& sig) {
  if (side == Side::Ecat) {
    sig.raise_al = (control & sm_bits::kAlEventEnable) != 0;
  } else {
    sig.raise_ecat = (control & sm_bits::kEcatEventEnable) != 0;
  }
}

// An access to the buffer acknowledges that side's pending interrupt.
inline void acknowledge(Side side, SmSignals& sig) {
  if (side == Side::Ecat) {
    sig.clear_ecat = true;
  } else {
    sig.clear_al = true;
  }
}

}  // namespace sm_detail

inline std::uint32_t SyncManager::buffered_read(Side side, std::uint16_t address, std::size_t n,
                                               SmSignals& sig) noexcept {
  // The reader takes the latest complete buffer when it opens one. The
  // status byte is updated once (same result as bit by bit).
  const bool first = address == start();
  const bool last = static_cast<std::uint32_t>(address) + n == end();
  const std::uint8_t ctl = control();
  std::uint8_t status = regs_[reg::sm::kStatus];
  if (first || !read_open_) {
    if (latest_ != sm_bits::kNoBufferWritten) read_buffer_ = latest_;
    read_open_ = true;
    sm_detail::acknowledge(side, sig);
    status = static_cast<std::uint8_t>((status & ~sm_bits::kStatusWriteEvent) | sm_bits::kStatusReadBufferOpen);
  }
  if (last) {
    read_open_ = false;
    status = static_cast<std::uint8_t>((status & ~sm_bits::kStatusReadBufferOpen) | sm_bits::kStatusReadEvent);
    sm_detail::signal_other_side(side, ctl, sig);
  }
  regs_[reg::sm::kStatus] = status;
  return physical(read_buffer_, address);
}

inline std::uint32_t SyncManager::buffered_write(Side side, std::uint16_t address, std::size_t n,
                                                SmSignals& sig) noexcept {
  // The status byte is updated once (same result as bit by bit).
  const bool first = address == start();
  const bool last = static_cast<std::uint32_t>(address) + n == end();
  const std::uint32_t at = physical(write_buffer_, address);
  const std::uint8_t ctl = control();
  std::uint8_t status = regs_[reg::sm::kStatus];
  if (first || !write_open_) {
    write_open_ = true;
    sm_detail::acknowledge(side, sig);
    status = static_cast<std::uint8_t>((status & ~sm_bits::kStatusReadEvent) | sm_bits::kStatusWriteBufferOpen);
  }
  if (last) {
    // Exchange: the written buffer becomes the latest; the writer continues
    // with the buffer neither the reader holds nor the latest is in.
    latest_ = write_buffer_;
    write_buffer_ = static_cast<std::uint8_t>(sm_detail::kBufferIndexSum - latest_ - read_buffer_);
    if (latest_ == read_buffer_) write_buffer_ = latest_ == 2 ? 1 : 2;
    write_open_ = false;
    status = static_cast<std::uint8_t>((status & ~(sm_bits::kStatusBufferMask | sm_bits::kStatusWriteBufferOpen)) |
                                       (latest_ << sm_bits::kStatusBufferShift) | sm_bits::kStatusWriteEvent);
    sm_detail::signal_other_side(side, ctl, sig);
    sig.watchdog_trigger = side == Side::Ecat && (ctl & sm_bits::kWatchdogTrigger) != 0;
  }
  regs_[reg::sm::kStatus] = status;
  return at;
}

inline bool SyncManager::read(Side side, std::uint16_t address, std::span<std::uint8_t> out, SmSignals& sig) noexcept {
  // The writing side cannot read the buffer; a deactivated SM blocks both.
  if (pdi_deactivated() || writer(side) || out.empty()) return false;
  if (!mailbox()) {
    sm_detail::copy_out(mem_, mem_end_, buffered_read(side, address, out.size(), sig), out);
    return true;
  }
  const bool last = static_cast<std::uint32_t>(address) + out.size() == end();
  const std::uint8_t ctl = control();
  if (!full_) return false;  // empty mailbox: no data, no WKC (Section I §8.2)
  sm_detail::copy_out(mem_, mem_end_, address, out);
  sm_detail::acknowledge(side, sig);
  set_status_bits(sm_bits::kStatusReadBufferOpen, sm_bits::kStatusWriteEvent);
  if (last) {
    full_ = false;
    set_status_bits(sm_bits::kStatusReadEvent, sm_bits::kStatusMailboxFull | sm_bits::kStatusReadBufferOpen);
    sm_detail::signal_other_side(side, ctl, sig);
  }
  return true;
}

// read() with first and last both true: the read buffer opens and closes.
inline void SyncManager::ecat_read_whole(std::uint8_t* out) noexcept {
  if (latest_ != sm_bits::kNoBufferWritten) read_buffer_ = latest_;
  read_open_ = false;
  const std::uint16_t len = length();
  std::memcpy(out, mem_ + start() + static_cast<std::uint32_t>(read_buffer_) * len, len);
  regs_[reg::sm::kStatus] = static_cast<std::uint8_t>(
      (regs_[reg::sm::kStatus] & ~(sm_bits::kStatusWriteEvent | sm_bits::kStatusReadBufferOpen)) |
      sm_bits::kStatusReadEvent);
}

// write() with first and last both true: fill, then exchange.
inline void SyncManager::ecat_write_whole(const std::uint8_t* in) noexcept {
  const std::uint16_t len = length();
  std::memcpy(mem_ + start() + static_cast<std::uint32_t>(write_buffer_) * len, in, len);
  latest_ = write_buffer_;
  write_buffer_ = static_cast<std::uint8_t>(sm_detail::kBufferIndexSum - latest_ - read_buffer_);
  if (latest_ == read_buffer_) write_buffer_ = latest_ == 2 ? 1 : 2;
  write_open_ = false;
  regs_[reg::sm::kStatus] = static_cast<std::uint8_t>(
      (regs_[reg::sm::kStatus] &
       ~(sm_bits::kStatusReadEvent | sm_bits::kStatusBufferMask | sm_bits::kStatusWriteBufferOpen)) |
      (latest_ << sm_bits::kStatusBufferShift) | sm_bits::kStatusWriteEvent);
}

inline bool SyncManager::write(Side side, std::uint16_t address, std::span<const std::uint8_t> in, SmSignals& sig) noexcept {
  if (pdi_deactivated() || !writer(side) || in.empty()) return false;
  if (!mailbox()) {
    sm_detail::copy_in(mem_, mem_end_, buffered_write(side, address, in.size(), sig), in);
    return true;
  }
  const bool last = static_cast<std::uint32_t>(address) + in.size() == end();
  const std::uint8_t ctl = control();
  const bool wd = side == Side::Ecat && (ctl & sm_bits::kWatchdogTrigger) != 0;
  if (full_) return false;  // full mailbox: not written, no WKC (Section I §8.2)
  sm_detail::copy_in(mem_, mem_end_, address, in);
  sm_detail::acknowledge(side, sig);
  set_status_bits(sm_bits::kStatusWriteBufferOpen, sm_bits::kStatusReadEvent);
  if (last) {
    full_ = true;
    set_status_bits(sm_bits::kStatusMailboxFull | sm_bits::kStatusWriteEvent, sm_bits::kStatusWriteBufferOpen);
    sm_detail::signal_other_side(side, ctl, sig);
    sig.watchdog_trigger = wd;
  }
  return true;
}

}  // namespace ecat::esc
