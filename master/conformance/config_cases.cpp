// Invalid SyncManager configurations and the watchdog (ETG.1000.6 §6.4.1,
// Table 11 codes 0x0016, 0x001D, 0x001E, 0x001B; esm-al-codes.md §3).
#include <fmt/format.h>

#include "master/conformance/suite.hpp"
#include "master/registers.hpp"

namespace ecat::master::conformance {

namespace {

constexpr std::uint16_t kInvalidMailboxConfig = 0x0016;
constexpr std::uint16_t kSmWatchdog = 0x001B;
constexpr std::uint16_t kSyncError = 0x001A;  // ETG.1000.6 Table 11: synchronization error
constexpr std::uint16_t kInvalidOutputConfig = 0x001D;
constexpr std::uint16_t kInvalidInputConfig = 0x001E;
// Watchdog base unit: (divider + 2) x 40 ns (esc-registers.md §8).
constexpr std::int64_t kWatchdogTickNs = 40;
constexpr std::int64_t kWatchdogWaitFactor = 3;
constexpr unsigned kWatchdogPolls = 20;

std::string refused(AlState s, std::uint16_t code) {
  AlStatus st;
  st.raw = static_cast<std::uint16_t>(static_cast<std::uint8_t>(s) | kAlErrorBit);
  st.code = code;
  return format_status(st);
}

std::string shown(const Expected<AlStatus, MasterError>& st) {
  return st ? format_status(*st) : std::string(describe(st.error()));
}

Case mailbox_case(const char* name, const char* what, void (*mutate)(MailboxLayout&, bool&)) {
  return Case{std::string("config.") + name,
              std::string("ETG.1000.6 §6.4.1 Init->PreOp mailbox check, Table 11 0x0016 (") + what + "; esm-al-codes.md §3)",
              [mutate](Context& ctx) {
                const SiiInfo& sii = ctx.info().sii;
                if (!sii.has_mailbox()) return CaseResult::skip("no mailbox");
                MailboxLayout l;
                l.rx_start = sii.rx_mailbox_offset;
                l.rx_size = sii.rx_mailbox_size;
                l.tx_start = sii.tx_mailbox_offset;
                l.tx_size = sii.tx_mailbox_size;
                if (sii.sync_managers.size() >= 2) {
                  l.rx_control = sii.sync_managers[0].control;
                  l.tx_control = sii.sync_managers[1].control;
                }
                bool enable = true;
                mutate(l, enable);
                if (auto r = ctx.master().write_mailbox_sms(ctx.slave(), l, enable); !r) {
                  return CaseResult::failed("SM0/SM1 written", std::string(describe(r.error())));
                }
                return CaseResult::compare(refused(AlState::Init, kInvalidMailboxConfig),
                                           shown(ctx.master().request_state(ctx.slave(), AlState::PreOp)));
              }};
}

// PreOp with process data prepared, then the first SM of a direction (SM2 or
// SM3 on most devices; SM0 for EK1828's outputs) rewritten by `mutate`, then SafeOp.
CaseResult process_sm_case(Context& ctx, bool outputs, std::uint16_t code,
                           void (*mutate)(std::uint16_t& start, std::uint16_t& length)) {
  if (auto r = ctx.go_to(AlState::PreOp); !r) return CaseResult::failed("reach PreOp", r.error());
  if (auto r = ctx.prepare_process_data(); !r) return CaseResult::failed("process data", r.error());
  const ProcessSm* p = ctx.info().pd.first(outputs);
  if (p == nullptr || p->bytes == 0) return CaseResult::skip(outputs ? "no outputs" : "no inputs");
  std::uint16_t start = p->start;
  std::uint16_t length = p->bytes;
  mutate(start, length);
  if (auto r = ctx.master().write_sync_manager(ctx.slave(), p->sm, start, length, p->control, true); !r) {
    return CaseResult::failed("SM written", std::string(describe(r.error())));
  }
  return CaseResult::compare(refused(AlState::PreOp, code),
                             shown(ctx.master().request_state(ctx.slave(), AlState::SafeOp)));
}

}  // namespace

std::vector<Case> config_cases() {
  std::vector<Case> cases{
      mailbox_case("mailbox_sm0_length", "SM0 length", [](MailboxLayout& l, bool&) { l.rx_size = static_cast<std::uint16_t>(l.rx_size - 2); }),
      mailbox_case("mailbox_sm1_start", "SM1 start", [](MailboxLayout& l, bool&) { l.tx_start = static_cast<std::uint16_t>(l.tx_start + 2); }),
      mailbox_case("mailbox_sm0_control", "SM0 control byte", [](MailboxLayout& l, bool&) { l.rx_control = l.tx_control; }),
      mailbox_case("mailbox_sm_disabled", "SM0/SM1 not enabled", [](MailboxLayout&, bool& e) { e = false; }),
  };
  cases.push_back({"config.output_sm_length", "ETG.1000.6 §6.4.1 PreOp->SafeOp, Table 11 0x001D (SM2 length != RxPDO size)",
                   [](Context& ctx) {
                     return process_sm_case(ctx, true, kInvalidOutputConfig,
                                            [](std::uint16_t&, std::uint16_t& len) { len = static_cast<std::uint16_t>(len + 1); });
                   }});
  cases.push_back({"config.input_sm_length", "ETG.1000.6 §6.4.1 PreOp->SafeOp, Table 11 0x001E (SM3 length != TxPDO size)",
                   [](Context& ctx) {
                     return process_sm_case(ctx, false, kInvalidInputConfig,
                                            [](std::uint16_t&, std::uint16_t& len) { len = static_cast<std::uint16_t>(len + 1); });
                   }});
  cases.push_back({"config.output_sm_start", "ETG.1000.6 §6.4.1 PreOp->SafeOp, Table 11 0x001D (SM2 start address)",
                   [](Context& ctx) {
                     return process_sm_case(ctx, true, kInvalidOutputConfig,
                                            [](std::uint16_t& start, std::uint16_t&) { start = static_cast<std::uint16_t>(start + 8); });
                   }});
  cases.push_back({"config.watchdog_expiry", "ETG.1000.6 Table 11 0x001B: no process data within the SM watchdog time -> SafeOp + ErrInd (esm-al-codes.md §5.6, esc-registers.md §8)",
                   [](Context& ctx) {
                     if (!ctx.options().wait) return CaseResult::skip("no way to let time pass");
                     if (auto r = ctx.go_to(AlState::Op); !r) return CaseResult::failed("reach Op", r.error());
                     const ProcessSm* out = ctx.info().pd.first(true);
                     if (ctx.info().pd.output_bytes == 0 || out == nullptr) return CaseResult::skip("no outputs (no SM2 watchdog)");
                     const std::uint16_t station = ctx.info().station_address;
                     // ESC Section II 0x0804 bit 6: only an SM with the watchdog trigger
                     // enabled rewinds the process-data watchdog; without it (e.g. control
                     // byte 0x24) the firmware does not supervise SM2 (SSC, SOES).
                     auto control = ctx.master().fprd_u8(
                         station, static_cast<std::uint16_t>(reg::sync_manager(out->sm) + reg::kSmControlOffset));
                     if (!control) return CaseResult::failed("SM2 control register", "read failed");
                     if ((*control & reg::kSmControlWatchdogTrigger) == 0) {
                       return CaseResult::skip(fmt::format("SM2 watchdog trigger not enabled (control byte 0x{:02X})", *control));
                     }
                     auto divider = ctx.master().fprd_u16(station, reg::kWatchdogDivider);
                     auto time = ctx.master().fprd_u16(station, reg::kWatchdogTimeProcessData);
                     if (!divider || !time) return CaseResult::failed("watchdog registers", "read failed");
                     if (*time == 0) return CaseResult::skip("process-data watchdog disabled (0x0420 = 0)");
                     const Nanoseconds wd{(static_cast<std::int64_t>(*divider) + 2) * kWatchdogTickNs * *time};
                     Expected<AlStatus, MasterError> st = fail(MasterError::Timeout);
                     for (unsigned i = 0; i < kWatchdogPolls; ++i) {
                       ctx.wait(wd * kWatchdogWaitFactor / kWatchdogPolls);
                       st = ctx.master().read_al_status(ctx.slave());
                       if (st && st->error()) break;
                     }
                     // In DC Sync0 mode the slave also checks for new outputs at every
                     // SYNC0 (ETG.1020 SM event missed, 1C32h:0B against 10F1h:02): that
                     // supervision expires first, with 0x001A (the twin, SSC-based drives).
                     if (ctx.options().dc && st && st->code == kSyncError) {
                       return CaseResult::pass(refused(AlState::SafeOp, kSmWatchdog) + " | " + refused(AlState::SafeOp, kSyncError) + " (DC)",
                                               shown(st));
                     }
                     return CaseResult::compare(refused(AlState::SafeOp, kSmWatchdog), shown(st));
                   }});
  cases.push_back({"config.sm2_disabled_in_safeop", "ETG.1000.6 §6.4.1 SM change at run time, Table 11 0x001D -> PreOp + ErrInd (esm-al-codes.md §3, SOES)",
                   [](Context& ctx) {
                     if (auto r = ctx.go_to(AlState::SafeOp); !r) return CaseResult::failed("reach SafeOp", r.error());
                     const ProcessSm* out = ctx.info().pd.first(true);
                     if (ctx.info().pd.output_bytes == 0 || out == nullptr) return CaseResult::skip("no outputs");
                     const auto act = static_cast<std::uint16_t>(reg::sync_manager(out->sm) + reg::kSmActivateOffset);
                     if (auto r = ctx.master().fpwr_u8(ctx.info().station_address, act, 0); !r) {
                       return CaseResult::failed("SM2 disabled", std::string(describe(r.error())));
                     }
                     auto st = ctx.master().read_al_status(ctx.slave());
                     for (unsigned i = 0; i < kWatchdogPolls && st && !st->error(); ++i) st = ctx.master().read_al_status(ctx.slave());
                     return CaseResult::compare(refused(AlState::PreOp, kInvalidOutputConfig), shown(st));
                   }});
  return cases;
}

}  // namespace ecat::master::conformance
