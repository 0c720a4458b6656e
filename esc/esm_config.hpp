// What the state machine expects the master to have configured before it
// allows a transition (ETG.1000.6 §6.4.1; shared/spec/esm-al-codes.md §3).
// Filled from the device description (SII words 0x14-0x1B, SYNCM category).
#pragma once

#include <array>
#include <cstdint>
#include <span>

namespace ecat::esc {

// Sync manager numbers fixed by ETG.1000.6 for a device with a mailbox.
inline constexpr unsigned kSmMailboxOut = 0;  // master -> slave
inline constexpr unsigned kSmMailboxIn = 1;   // slave -> master
inline constexpr unsigned kSmOutputs = 2;
inline constexpr unsigned kSmInputs = 3;

// A mailbox SM must match start, length and control byte exactly.
struct MailboxSmConfig {
  std::uint16_t start = 0;
  std::uint16_t length = 0;
  std::uint8_t control = 0;
};

// A process-data SM: start and control must match; its length comes from the
// PDO mapping and is checked by the CoE hook. A device may have several per
// direction (Beckhoff EK1828: outputs on SM0 at 0F00h and SM1 at 0F01h,
// inputs on SM2; ETG.1000.6 §5.6.7.4: SM n carries what 1C10h+n assigns).
struct ProcessSmConfig {
  std::uint8_t sm = 0;   // SM number
  bool outputs = false;  // master -> slave (0x001D when wrong), else inputs (0x001E)
  std::uint16_t start = 0;
  std::uint8_t control = 0;
};

// SMs of an ESC (Section II 0x0005: at most 16; the device model keeps 8).
inline constexpr unsigned kMaxProcessSms = 8;

struct EsmConfig {
  bool has_mailbox = true;
  MailboxSmConfig mailbox_out{};  // SM0 in PreOp and above
  MailboxSmConfig mailbox_in{};   // SM1
  bool bootstrap_supported = false;
  MailboxSmConfig boot_mailbox_out{};  // SM0 in Bootstrap
  MailboxSmConfig boot_mailbox_in{};   // SM1 in Bootstrap
  // The process-data SMs the firmware checks at PreOp->SafeOp and serves in
  // SafeOp/Op, in SM order. A direction the device has no PDOs for is not
  // listed: its SM is not checked, as SSC compiled without that direction
  // (MAX_PD_OUTPUT_SIZE 0) does not check SM2 (docs/twins.md "An enabled SM
  // for a direction without process data").
  std::array<ProcessSmConfig, kMaxProcessSms> process_sms{};
  std::uint8_t process_sm_count = 0;
  // Appends one; false when the list is full.
  bool add_process_sm(ProcessSmConfig sm) noexcept {
    if (process_sm_count == kMaxProcessSms) return false;
    process_sms[process_sm_count++] = sm;
    return true;
  }
  std::span<const ProcessSmConfig> process() const noexcept { return {process_sms.data(), process_sm_count}; }
  // SafeOp->Op only once the process-data watchdog (0x0440 bit 0) shows that
  // outputs arrive; ETG wording, SOES does not wait (esm-al-codes.md §3).
  bool op_requires_outputs = false;
  // Device identification value for AL control bit 5; 0 = use the station
  // alias 0x0012 (SOES ESC_load_device_id).
  std::uint16_t device_id = 0;
};

}  // namespace ecat::esc
