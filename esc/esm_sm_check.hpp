// Sync manager checks the state machine makes before Init->PreOp, Init->Boot
// and PreOp->SafeOp, and again when the master changes a SM at run time
// (ETG.1000.6 §6.4.1, SOES ESC_checkmbx / ESC_checkSM23).
#pragma once

#include <cstdint>

#include "esc/al_status_code.hpp"
#include "esc/esm_config.hpp"
#include "esc/pdi.hpp"

namespace ecat::esc {

// One SM's 8-byte register block (ESC datasheet Section II 0x0800+8n).
struct SmRegisters {
  std::uint16_t start = 0;
  std::uint16_t length = 0;
  std::uint8_t control = 0;
  std::uint8_t status = 0;
  std::uint8_t activate = 0;
  std::uint8_t pdi_control = 0;

  bool enabled() const noexcept;
  // Bytes the SM occupies: 3 x length in buffered mode, length in mailbox
  // mode and for length 1 (a watchdog trigger only, Section II 0x0802).
  std::uint32_t footprint() const noexcept;
};

// Reads the block through the PDI (reading clears AL event 0x0220 bit 4).
SmRegisters read_sm(Pdi& pdi, unsigned n) noexcept;

// SM0/SM1 against the expected mailbox layout: both enabled, start, length
// and control equal. `code` is 0x0016 (PreOp) or 0x0015 (Bootstrap).
AlStatusCode check_mailbox(Pdi& pdi, const MailboxSmConfig& out, const MailboxSmConfig& in,
                           AlStatusCode code) noexcept;

// The process-data SMs of the config (SM2/SM3, or as many per direction as
// the device has) at PreOp->SafeOp: an SM with length 0 must be disabled;
// with a length it must be enabled with the expected start and control byte
// (0x001D outputs, 0x001E inputs; inputs win as in SOES).
AlStatusCode check_process_sms(Pdi& pdi, const EsmConfig& config) noexcept;

// Enabled SM areas (SM0..SM7) must not overlap (0x0017); an SM of length 1
// holds no buffers (Section II 0x0802). At PreOp->SafeOp this comes after
// the SM lengths are checked against the mapping (SSC: CheckSmSettings, then
// the overlap check of StartInputHandler), so a wrong length is reported as
// 0x001D/0x001E, not as the overlap it makes.
AlStatusCode check_sm_overlap(Pdi& pdi) noexcept;

// Sets or clears the PDI deactivate bit (0x0807+8n bit 0) keeping the
// repeat-acknowledge bit.
void set_sm_deactivated(Pdi& pdi, unsigned n, bool deactivated) noexcept;

}  // namespace ecat::esc
