// Sync manager checks of the state machine (ETG.1000.6 §6.4.1; ESC datasheet
// Section II SM registers; shared/spec/esm-al-codes.md §3, esc-registers.md §7).
#include "esc/esm_sm_check.hpp"

#include <array>

#include "esc/registers.hpp"

namespace ecat::esc {
namespace {

constexpr std::uint8_t kActivateEnable = 0x01;    // activate byte bit 0
constexpr std::uint8_t kPdiDeactivate = 0x01;     // PDI control byte bit 0
constexpr std::uint8_t kControlModeMask = 0x03;   // control bits 1:0
constexpr std::uint8_t kControlModeBuffered = 0x00;
constexpr std::uint32_t kBuffersInBufferedMode = 3;
// Section II 0x0802: a length of 1 does not activate the SM ("only Watchdog
// Trigger is generated"): its byte is plain memory, no buffers.
constexpr std::uint16_t kWatchdogOnlyLength = 1;
constexpr unsigned kCheckedSms = kMaxProcessSms;  // SM0..SM7 for the overlap check

bool mailbox_matches(const SmRegisters& sm, const MailboxSmConfig& expected) noexcept {
  return sm.enabled() && sm.start == expected.start && sm.length == expected.length &&
         sm.control == expected.control;
}

bool process_sm_ok(const SmRegisters& sm, const ProcessSmConfig& expected) noexcept {
  // An SM that starts and is controlled as expected; with length 0 it must be off.
  if (sm.length == 0) return !sm.enabled();
  return sm.enabled() && sm.start == expected.start && sm.control == expected.control;
}

bool overlap(const SmRegisters& a, const SmRegisters& b) noexcept {
  const std::uint32_t a_end = a.start + a.footprint();
  const std::uint32_t b_end = b.start + b.footprint();
  return a.start < b_end && b.start < a_end;
}

}  // namespace

bool SmRegisters::enabled() const noexcept { return (activate & kActivateEnable) != 0; }

std::uint32_t SmRegisters::footprint() const noexcept {
  const bool buffered = (control & kControlModeMask) == kControlModeBuffered && length != kWatchdogOnlyLength;
  return buffered ? kBuffersInBufferedMode * length : length;
}

SmRegisters read_sm(Pdi& pdi, unsigned n) noexcept {
  std::array<std::uint8_t, reg::kSyncManagerStride> b{};
  pdi.read(reg::sync_manager(n), b);
  SmRegisters sm;
  sm.start = load_le<std::uint16_t>(&b[reg::sm::kStartAddress]);
  sm.length = load_le<std::uint16_t>(&b[reg::sm::kLength]);
  sm.control = b[reg::sm::kControl];
  sm.status = b[reg::sm::kStatus];
  sm.activate = b[reg::sm::kActivate];
  sm.pdi_control = b[reg::sm::kPdiControl];
  return sm;
}

AlStatusCode check_mailbox(Pdi& pdi, const MailboxSmConfig& out, const MailboxSmConfig& in,
                           AlStatusCode code) noexcept {
  const SmRegisters sm0 = read_sm(pdi, kSmMailboxOut);
  const SmRegisters sm1 = read_sm(pdi, kSmMailboxIn);
  if (!mailbox_matches(sm0, out) || !mailbox_matches(sm1, in)) return code;
  return AlStatusCode::NoError;
}

AlStatusCode check_process_sms(Pdi& pdi, const EsmConfig& config) noexcept {
  std::array<SmRegisters, kCheckedSms> sms{};
  for (const ProcessSmConfig& p : config.process()) {
    if (p.sm < kCheckedSms) sms[p.sm] = read_sm(pdi, p.sm);
  }
  // Every inputs SM first, then every outputs SM: SOES reports 0x001E when
  // an input SM failed, else 0x001D (esm-al-codes.md §3), SM by SM here.
  for (const bool outputs : {false, true}) {
    for (const ProcessSmConfig& p : config.process()) {
      if (p.outputs != outputs || p.sm >= kCheckedSms) continue;
      if (!process_sm_ok(sms[p.sm], p)) {
        return outputs ? AlStatusCode::InvalidOutputConfiguration : AlStatusCode::InvalidInputConfiguration;
      }
    }
  }
  return AlStatusCode::NoError;
}

AlStatusCode check_sm_overlap(Pdi& pdi) noexcept {
  std::array<SmRegisters, kCheckedSms> sms{};
  for (unsigned n = 0; n < kCheckedSms; ++n) sms[n] = read_sm(pdi, n);
  for (unsigned a = 0; a < kCheckedSms; ++a) {
    for (unsigned b = a + 1; b < kCheckedSms; ++b) {
      if (sms[a].enabled() && sms[b].enabled() && sms[a].length > 0 && sms[b].length > 0 &&
          overlap(sms[a], sms[b])) {
        return AlStatusCode::InvalidSyncManagerConfiguration;
      }
    }
  }
  return AlStatusCode::NoError;
}

void set_sm_deactivated(Pdi& pdi, unsigned n, bool deactivated) noexcept {
  const auto address = static_cast<std::uint16_t>(reg::sync_manager(n) + reg::sm::kPdiControl);
  std::uint8_t v = pdi.read_u8(address);
  v = deactivated ? static_cast<std::uint8_t>(v | kPdiDeactivate)
                  : static_cast<std::uint8_t>(v & ~kPdiDeactivate);
  pdi.write_u8(address, v);
}

}  // namespace ecat::esc
