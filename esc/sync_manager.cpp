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

}  // namespace ecat::esc
