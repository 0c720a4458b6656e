// One SyncManager: consistent, protected access to a buffer in process RAM
// shared by the EtherCAT side and the PDI (ESC datasheet Section I §8,
// Section II 0x0800+8n; ETG.1000.4 §6.7; shared/spec/esc-registers.md §7).
// Mailbox (1-buffer) and buffered (3-buffer) modes, direction, activation,
// PDI deactivation, status byte and the interrupt bits. The register bytes
// live in the ESC memory; this object keeps the buffer state behind them.
#pragma once

#include <cstdint>
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
  bool mailbox() const noexcept;
  // True for master->slave buffers (ECAT writes, PDI reads).
  bool ecat_writes() const noexcept;
  // Enabled by ECAT (0x0806 bit 0), length >= 2: guards its buffer area.
  bool enabled() const noexcept;
  bool pdi_deactivated() const noexcept;
  bool covers(std::uint32_t address) const noexcept;
  std::uint32_t end() const noexcept { return static_cast<std::uint32_t>(start()) + length(); }
  bool mailbox_full() const noexcept { return full_; }

  // An access to [address, address + data.size()) that lies fully inside
  // this SM's area, from `side`. Copies the data if allowed (redirecting to
  // the current 3-buffer). Returns true if carried out.
  bool read(Side side, std::uint16_t address, std::span<std::uint8_t> out, SmSignals& sig) noexcept;
  bool write(Side side, std::uint16_t address, std::span<const std::uint8_t> in, SmSignals& sig) noexcept;

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

}  // namespace ecat::esc
