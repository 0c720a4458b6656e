// SyncManager buffer rules (ESC datasheet Section I §8.1 buffered mode,
// §8.2 mailbox mode, §8.3 PDI deactivation; Section II 0x0800-0x087F).
#include "esc/sync_manager.hpp"

#include <algorithm>
#include <cstring>

#include "common/le.hpp"
#include "esc/registers.hpp"

namespace ecat::esc {

using namespace sm_bits;

void SyncManager::bind(std::uint8_t* regs, std::uint8_t* memory, std::uint32_t memory_end) noexcept {
  regs_ = regs;
  mem_ = memory;
  mem_end_ = memory_end;
  reset_state();
}

bool SyncManager::mailbox() const noexcept { return (control() & kModeMask) == kModeMailbox; }
bool SyncManager::ecat_writes() const noexcept { return (control() & kDirectionMask) == kDirectionWrite; }
bool SyncManager::enabled() const noexcept {
  return (regs_[reg::sm::kActivate] & kActivateEnable) != 0 && length() >= kMinActiveLength;
}
bool SyncManager::pdi_deactivated() const noexcept { return (regs_[reg::sm::kPdiControl] & kPdiDeactivate) != 0; }
bool SyncManager::covers(std::uint32_t address) const noexcept {
  return enabled() && address >= start() && address < end();
}

void SyncManager::reset_state() noexcept {
  full_ = false;
  read_buffer_ = 0;
  latest_ = kNoBufferWritten;
  write_buffer_ = 1;
  read_open_ = false;
  write_open_ = false;
  // Status: nothing written yet; buffered mode shows "no buffer" (3) in bits 5:4.
  regs_[reg::sm::kStatus] = mailbox() ? 0 : static_cast<std::uint8_t>(kNoBufferWritten << kStatusBufferShift);
}

void SyncManager::on_register_written(unsigned offset, std::uint8_t old_value) noexcept {
  if (offset == reg::sm::kActivate) {
    // Enabling or disabling restarts the buffer state; a repeat-request
    // toggle alone leaves it (Section I §8.2.1: the PDI re-writes the buffer).
    if ((old_value ^ regs_[offset]) & kActivateEnable) reset_state();
  } else if (offset == reg::sm::kPdiControl) {
    if ((old_value ^ regs_[offset]) & kPdiDeactivate) reset_state();
  } else if (offset <= reg::sm::kControl) {
    reset_state();
  }
}

std::uint32_t SyncManager::physical(std::uint8_t buffer, std::uint16_t address) const noexcept {
  return static_cast<std::uint32_t>(address) + static_cast<std::uint32_t>(buffer) * length();
}

void SyncManager::set_status_bits(std::uint8_t set, std::uint8_t clear) noexcept {
  regs_[reg::sm::kStatus] = static_cast<std::uint8_t>((regs_[reg::sm::kStatus] & ~clear) | set);
}

namespace {
constexpr unsigned kBufferIndexSum = 0 + 1 + 2;  // the three buffers of buffered mode

// Copies, clipped at the end of ESC memory (bytes past it read as 0 / are dropped).
void copy_out(const std::uint8_t* mem, std::uint32_t mem_end, std::uint32_t at, std::span<std::uint8_t> out) {
  std::size_t n = at >= mem_end ? 0 : std::min<std::size_t>(out.size(), mem_end - at);
  if (n) std::memcpy(out.data(), mem + at, n);
  if (n < out.size()) std::memset(out.data() + n, 0, out.size() - n);
}
void copy_in(std::uint8_t* mem, std::uint32_t mem_end, std::uint32_t at, std::span<const std::uint8_t> in) {
  std::size_t n = at >= mem_end ? 0 : std::min<std::size_t>(in.size(), mem_end - at);
  if (n) std::memcpy(mem + at, in.data(), n);
}
}  // namespace

// The interrupt for the other side, when `side` completed a buffer.
static void signal_other_side(Side side, std::uint8_t control, SmSignals& sig) {
  if (side == Side::Ecat) {
    sig.raise_al = (control & kAlEventEnable) != 0;
  } else {
    sig.raise_ecat = (control & kEcatEventEnable) != 0;
  }
}

// An access to the buffer acknowledges that side's pending interrupt.
static void acknowledge(Side side, SmSignals& sig) {
  if (side == Side::Ecat) {
    sig.clear_ecat = true;
  } else {
    sig.clear_al = true;
  }
}

bool SyncManager::read(Side side, std::uint16_t address, std::span<std::uint8_t> out, SmSignals& sig) noexcept {
  // The writing side cannot read the buffer; a deactivated SM blocks both.
  if (pdi_deactivated() || writer(side) || out.empty()) return false;
  const bool first = address == start();
  const bool last = static_cast<std::uint32_t>(address) + out.size() == end();
  const std::uint8_t ctl = control();
  if ((ctl & kModeMask) != kModeMailbox) {
    // Buffered: the reader takes the latest complete buffer when it opens
    // one. The status byte is updated once (same result as bit by bit).
    std::uint8_t status = regs_[reg::sm::kStatus];
    if (first || !read_open_) {
      if (latest_ != kNoBufferWritten) read_buffer_ = latest_;
      read_open_ = true;
      acknowledge(side, sig);
      status = static_cast<std::uint8_t>((status & ~kStatusWriteEvent) | kStatusReadBufferOpen);
    }
    copy_out(mem_, mem_end_, physical(read_buffer_, address), out);
    if (last) {
      read_open_ = false;
      status = static_cast<std::uint8_t>((status & ~kStatusReadBufferOpen) | kStatusReadEvent);
      signal_other_side(side, ctl, sig);
    }
    regs_[reg::sm::kStatus] = status;
    return true;
  }
  if (!full_) return false;  // empty mailbox: no data, no WKC (Section I §8.2)
  copy_out(mem_, mem_end_, address, out);
  acknowledge(side, sig);
  set_status_bits(kStatusReadBufferOpen, kStatusWriteEvent);
  if (last) {
    full_ = false;
    set_status_bits(kStatusReadEvent, kStatusMailboxFull | kStatusReadBufferOpen);
    signal_other_side(side, ctl, sig);
  }
  return true;
}

bool SyncManager::write(Side side, std::uint16_t address, std::span<const std::uint8_t> in, SmSignals& sig) noexcept {
  if (pdi_deactivated() || !writer(side) || in.empty()) return false;
  const bool first = address == start();
  const bool last = static_cast<std::uint32_t>(address) + in.size() == end();
  const std::uint8_t ctl = control();
  const bool wd = side == Side::Ecat && (ctl & kWatchdogTrigger) != 0;
  if ((ctl & kModeMask) != kModeMailbox) {
    // Buffered; the status byte is updated once (same result as bit by bit).
    std::uint8_t status = regs_[reg::sm::kStatus];
    if (first || !write_open_) {
      write_open_ = true;
      acknowledge(side, sig);
      status = static_cast<std::uint8_t>((status & ~kStatusReadEvent) | kStatusWriteBufferOpen);
    }
    copy_in(mem_, mem_end_, physical(write_buffer_, address), in);
    if (last) {
      // Exchange: the written buffer becomes the latest; the writer continues
      // with the buffer neither the reader holds nor the latest is in.
      latest_ = write_buffer_;
      write_buffer_ = static_cast<std::uint8_t>(kBufferIndexSum - latest_ - read_buffer_);
      if (latest_ == read_buffer_) write_buffer_ = latest_ == 2 ? 1 : 2;
      write_open_ = false;
      status = static_cast<std::uint8_t>((status & ~(kStatusBufferMask | kStatusWriteBufferOpen)) |
                                         (latest_ << kStatusBufferShift) | kStatusWriteEvent);
      signal_other_side(side, ctl, sig);
      sig.watchdog_trigger = wd;
    }
    regs_[reg::sm::kStatus] = status;
    return true;
  }
  if (full_) return false;  // full mailbox: not written, no WKC (Section I §8.2)
  copy_in(mem_, mem_end_, address, in);
  acknowledge(side, sig);
  set_status_bits(kStatusWriteBufferOpen, kStatusReadEvent);
  if (last) {
    full_ = true;
    set_status_bits(kStatusMailboxFull | kStatusWriteEvent, kStatusWriteBufferOpen);
    signal_other_side(side, ctl, sig);
    sig.watchdog_trigger = wd;
  }
  return true;
}

}  // namespace ecat::esc
