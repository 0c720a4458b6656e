// What the state machine expects the master to have configured before it
// allows a transition (ETG.1000.6 §6.4.1; shared/spec/esm-al-codes.md §3).
// Filled from the device description (SII words 0x14-0x1B, SYNCM category).
#pragma once

#include <cstdint>

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
// PDO mapping and is checked by the CoE hook.
struct ProcessSmConfig {
  std::uint16_t start = 0;
  std::uint8_t control = 0;
};

struct EsmConfig {
  bool has_mailbox = true;
  MailboxSmConfig mailbox_out{};  // SM0 in PreOp and above
  MailboxSmConfig mailbox_in{};   // SM1
  bool bootstrap_supported = false;
  MailboxSmConfig boot_mailbox_out{};  // SM0 in Bootstrap
  MailboxSmConfig boot_mailbox_in{};   // SM1 in Bootstrap
  ProcessSmConfig outputs{};  // SM2
  ProcessSmConfig inputs{};   // SM3
  // SafeOp->Op only once the process-data watchdog (0x0440 bit 0) shows that
  // outputs arrive; ETG wording, SOES does not wait (esm-al-codes.md §3).
  bool op_requires_outputs = false;
  // Device identification value for AL control bit 5; 0 = use the station
  // alias 0x0012 (SOES ESC_load_device_id).
  std::uint16_t device_id = 0;
};

}  // namespace ecat::esc
