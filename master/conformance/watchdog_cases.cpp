// The process-data watchdog (ESC Section II 0x0400-0x0443, Section I §10;
// ETG.1000.6 Table 11 0x001B; shared/spec/esc-registers.md §8,
// esm-al-codes.md §5.6): the time the divider and 0x0420 give, the expiry
// in Op, the status and counter registers, disabling with time 0, and the
// digital outputs the ESC clears. config.watchdog_expiry (config_cases.cpp)
// checks the expiry with the slave's own settings; these program them.
#include <fmt/format.h>

#include "master/conformance/suite.hpp"
#include "master/registers.hpp"

namespace ecat::master::conformance {

namespace {

constexpr std::uint16_t kWatchdogStatus = 0x0440;
constexpr std::uint16_t kWatchdogCounterPd = 0x0442;
constexpr std::uint16_t kDigitalOutputs = 0x0F00;
constexpr std::uint16_t kPdiControl = 0x0140;
constexpr std::uint8_t kWatchdogActive = 0x01;  // 0x0440 bit 0: 1 active or disabled, 0 expired
constexpr std::uint8_t kCounterMax = 0xFF;
constexpr std::uint16_t kSmWatchdog = 0x001B;
constexpr std::int64_t kTickNs = 40;  // 25 MHz: unit = (divider + 2) x 40 ns
// The time the cases program: long against a frame (50 µs in-process) and
// against a µC's reaction, short against the suite's run time.
constexpr Nanoseconds kTarget = std::chrono::milliseconds(20);
// Not expired at 70 % of the time; expired (SafeOp + 0x001B) by 150 %.
constexpr int kEarlyPercent = 70;
constexpr int kLatePercent = 150;
constexpr unsigned kPolls = 20;
// Digital I/O PDIs (0x0140: 0x04 digital I/O, 0x10-0x14 32-bit variants), whose
// outputs 0x0F00 the ESC itself drives (esc-registers.md §4.9, §8).
constexpr std::uint8_t kPdiDigitalIo = 0x04;
constexpr std::uint8_t kPdiDigitalIo32First = 0x10, kPdiDigitalIo32Last = 0x14;
constexpr std::uint8_t kOutputPattern = 0xA5;

std::string shown(const Expected<AlStatus, MasterError>& st) { return st ? format_status(*st) : std::string(describe(st.error())); }

std::string refused_safeop() {
  AlStatus s;
  s.raw = static_cast<std::uint16_t>(static_cast<std::uint8_t>(AlState::SafeOp) | kAlErrorBit);
  s.code = kSmWatchdog;
  return format_status(s);
}

// The watchdog the cases need: outputs with the trigger bit, a way to wait,
// free run (in DC Sync0 mode the SYNC supervision, 0x001A, comes first).
std::optional<CaseResult> need_watchdog(Context& ctx) {
  if (!ctx.options().wait) return CaseResult::skip("no way to let time pass");
  if (ctx.options().dc) return CaseResult::skip("DC Sync0 mode: the SYNC supervision (0x001A) ends Op before the process-data watchdog");
  if (auto r = ctx.go_to(AlState::PreOp); !r) return CaseResult::failed("reach PreOp", r.error());
  if (auto r = ctx.prepare_process_data(); !r) return CaseResult::failed("process data", r.error());
  const ProcessSm* out = ctx.info().pd.first(true);
  if (out == nullptr || ctx.info().pd.output_bytes == 0) return CaseResult::skip("no outputs (no SM with the watchdog trigger)");
  auto control = ctx.master().fprd_u8(ctx.info().station_address,
                                      static_cast<std::uint16_t>(reg::sync_manager(out->sm) + reg::kSmControlOffset));
  if (!control) return CaseResult::failed("SM control readable", std::string(describe(control.error())));
  if ((*control & reg::kSmControlWatchdogTrigger) == 0) {
    return CaseResult::skip(fmt::format("SM{} watchdog trigger not enabled (control byte 0x{:02X})", out->sm, *control));
  }
  return std::nullopt;
}

// Writes divider and time, restoring both when it goes out of scope.
class WatchdogSetting {
 public:
  explicit WatchdogSetting(Context& ctx) : ctx_(ctx) {
    auto d = ctx.master().fprd_u16(station(), reg::kWatchdogDivider);
    auto t = ctx.master().fprd_u16(station(), reg::kWatchdogTimeProcessData);
    ok_ = d && t;
    if (ok_) divider_ = *d, time_ = *t;
  }
  ~WatchdogSetting() {
    if (!ok_) return;
    (void)ctx_.master().fpwr_u16(station(), reg::kWatchdogDivider, divider_);
    (void)ctx_.master().fpwr_u16(station(), reg::kWatchdogTimeProcessData, time_);
  }
  WatchdogSetting(const WatchdogSetting&) = delete;
  WatchdogSetting& operator=(const WatchdogSetting&) = delete;
  bool ok() const noexcept { return ok_; }
  std::uint16_t divider() const noexcept { return divider_; }
  // Programs `divider` and the time value that gives kTarget with it.
  Expected<std::uint16_t, std::string> program(std::uint16_t divider) {
    const std::int64_t unit = (std::int64_t{divider} + 2) * kTickNs;
    const auto time = static_cast<std::uint16_t>(kTarget.count() / unit);
    if (auto r = ctx_.master().fpwr_u16(station(), reg::kWatchdogDivider, divider); !r) return fail(fmt::format("0x0400 write: {}", describe(r.error())));
    if (auto r = ctx_.master().fpwr_u16(station(), reg::kWatchdogTimeProcessData, time); !r) return fail(fmt::format("0x0420 write: {}", describe(r.error())));
    auto back_d = ctx_.master().fprd_u16(station(), reg::kWatchdogDivider);
    auto back_t = ctx_.master().fprd_u16(station(), reg::kWatchdogTimeProcessData);
    if (!back_d || !back_t || *back_d != divider || *back_t != time) {
      return fail(fmt::format("0x0400/0x0420 read back {}/{} after writing {}/{}", back_d ? hex(*back_d, 4) : "?",
                              back_t ? hex(*back_t, 4) : "?", hex(divider, 4), hex(time, 4)));
    }
    return time;
  }

 private:
  std::uint16_t station() const { return ctx_.info().station_address; }
  Context& ctx_;
  bool ok_ = false;
  std::uint16_t divider_ = 0, time_ = 0;
};

// Op, then no frames with outputs: not expired at 70 % of kTarget, SafeOp +
// 0x001B by 150 %.
CaseResult expiry_window(Context& ctx, WatchdogSetting& wd, std::uint16_t divider) {
  auto time = wd.program(divider);
  if (!time) return CaseResult::failed("watchdog programmed", time.error());
  if (auto r = ctx.go_to(AlState::Op); !r) return CaseResult::failed("reach Op", r.error());
  const std::string want = fmt::format("Op at {}% of {} ms, {} by {}% (divider {}, time {})", kEarlyPercent, kTarget.count() / 1'000'000,
                                       refused_safeop(), kLatePercent, hex(divider, 4), hex(*time, 4));
  const Nanoseconds start = ctx.master().clock().now();
  ctx.wait(kTarget * kEarlyPercent / 100);
  auto early = ctx.master().read_al_status(ctx.slave());
  if (!early || early->error() || !early->is(AlState::Op)) {
    return CaseResult::failed(want, fmt::format("{} after {} µs", shown(early), (ctx.master().clock().now() - start).count() / 1000));
  }
  Expected<AlStatus, MasterError> st = early;
  const Nanoseconds step = kTarget * (kLatePercent - kEarlyPercent) / 100 / kPolls;
  for (unsigned i = 0; i < kPolls && st && !st->error(); ++i) {
    ctx.wait(step);
    st = ctx.master().read_al_status(ctx.slave());
  }
  if (!st || shown(st) != refused_safeop()) {
    return CaseResult::failed(want, fmt::format("{} after {} µs", shown(st), (ctx.master().clock().now() - start).count() / 1000));
  }
  return CaseResult::pass(want, want);
}

}  // namespace

std::vector<Case> watchdog_cases() {
  std::vector<Case> cases;
  cases.push_back({"wd.expiry_time", "ESC Section II 0x0400/0x0420: expiry after (divider + 2) x 40 ns x time, here 20 ms; ETG.1000.6 Table 11 0x001B -> SafeOp + ErrInd (esc-registers.md §8, esm-al-codes.md §5.6)",
                   [](Context& ctx) {
                     if (auto c = need_watchdog(ctx)) return *c;
                     WatchdogSetting wd(ctx);
                     if (!wd.ok()) return CaseResult::failed("0x0400/0x0420 readable", "read failed");
                     return expiry_window(ctx, wd, wd.divider());
                   }});
  cases.push_back({"wd.divider_scaling", "ESC Section II 0x0400: the divider sets the unit of 0x0420 - a doubled unit with half the time value expires after the same 20 ms (esc-registers.md §8)",
                   [](Context& ctx) {
                     if (auto c = need_watchdog(ctx)) return *c;
                     WatchdogSetting wd(ctx);
                     if (!wd.ok()) return CaseResult::failed("0x0400/0x0420 readable", "read failed");
                     const auto doubled = static_cast<std::uint16_t>(2 * (wd.divider() + 2) - 2);
                     return expiry_window(ctx, wd, doubled);
                   }});
  cases.push_back({"wd.status_and_counter", "ESC Section II 0x0440 bit 0 (1 running, 0 expired) and 0x0442 (+1 per expiry, a write clears it) (esc-registers.md §8)",
                   [](Context& ctx) {
                     if (auto c = need_watchdog(ctx)) return *c;
                     WatchdogSetting wd(ctx);
                     if (!wd.ok()) return CaseResult::failed("0x0400/0x0420 readable", "read failed");
                     if (auto t = wd.program(wd.divider()); !t) return CaseResult::failed("watchdog programmed", t.error());
                     if (auto r = ctx.go_to(AlState::Op); !r) return CaseResult::failed("reach Op", r.error());
                     const std::uint16_t station = ctx.info().station_address;
                     auto running = ctx.master().fprd_u8(station, kWatchdogStatus);
                     auto before = ctx.master().fprd_u8(station, kWatchdogCounterPd);
                     if (!running || !before) return CaseResult::failed("0x0440/0x0442 readable", "read failed");
                     ctx.wait(kTarget * kLatePercent / 100);
                     auto expired = ctx.master().fprd_u8(station, kWatchdogStatus);
                     auto after = ctx.master().fprd_u8(station, kWatchdogCounterPd);
                     (void)ctx.master().fpwr_u8(station, kWatchdogCounterPd, 0);
                     auto cleared = ctx.master().fprd_u8(station, kWatchdogCounterPd);
                     if (!expired || !after || !cleared) return CaseResult::failed("0x0440/0x0442 readable", "read failed");
                     const int next = *before == kCounterMax ? kCounterMax : *before + 1;
                     return CaseResult::compare(
                         fmt::format("0x0440 bit 0 running 1, expired 0; 0x0442 {} -> {}, 0 after a write", *before, next),
                         fmt::format("0x0440 bit 0 running {}, expired {}; 0x0442 {} -> {}, {} after a write", *running & kWatchdogActive,
                                     *expired & kWatchdogActive, *before, *after, *cleared));
                   }});
  cases.push_back({"wd.disabled_with_time_zero", "ESC Section II 0x0420 = 0 disables the process-data watchdog: Op stays without frames for 3 x the default 100 ms, 0x0440 bit 0 = 1 (esc-registers.md §8)",
                   [](Context& ctx) {
                     if (auto c = need_watchdog(ctx)) return *c;
                     WatchdogSetting wd(ctx);
                     if (!wd.ok()) return CaseResult::failed("0x0400/0x0420 readable", "read failed");
                     const std::uint16_t station = ctx.info().station_address;
                     if (auto r = ctx.master().fpwr_u16(station, reg::kWatchdogTimeProcessData, 0); !r) {
                       return CaseResult::failed("0x0420 = 0 written", std::string(describe(r.error())));
                     }
                     if (auto r = ctx.go_to(AlState::Op); !r) return CaseResult::failed("reach Op", r.error());
                     constexpr Nanoseconds kDefault = std::chrono::milliseconds(100);
                     ctx.wait(3 * kDefault);
                     auto st = ctx.master().read_al_status(ctx.slave());
                     auto status = ctx.master().fprd_u8(station, kWatchdogStatus);
                     return CaseResult::compare("Op, 0x0440 bit 0 = 1",
                                                shown(st) + ", 0x0440 bit 0 = " + (status ? std::to_string(*status & kWatchdogActive) : "?"));
                   }});
  cases.push_back({"wd.digital_outputs_cleared", "ESC Section I §10 / Section II 0x0440, 0x0F00: with a digital I/O PDI the ESC drives the outputs 0x0F00-0x0F03 to 0 when the process-data watchdog expires (esc-registers.md §8)",
                   [](Context& ctx) {
                     auto pdi = ctx.master().fprd_u8(ctx.info().station_address, kPdiControl);
                     if (!pdi) return CaseResult::failed("0x0140 readable", std::string(describe(pdi.error())));
                     const bool digital = *pdi == kPdiDigitalIo || (*pdi >= kPdiDigitalIo32First && *pdi <= kPdiDigitalIo32Last);
                     if (!digital) {
                       return CaseResult::skip(fmt::format("PDI 0x0140 = 0x{:02X} is not digital I/O: the outputs' safe state is the application's (config.watchdog_expiry)", *pdi));
                     }
                     if (auto c = need_watchdog(ctx)) return *c;
                     WatchdogSetting wd(ctx);
                     if (!wd.ok()) return CaseResult::failed("0x0400/0x0420 readable", "read failed");
                     if (auto t = wd.program(wd.divider()); !t) return CaseResult::failed("watchdog programmed", t.error());
                     if (auto r = ctx.go_to(AlState::Op); !r) return CaseResult::failed("reach Op", r.error());
                     const std::uint16_t station = ctx.info().station_address;
                     (void)ctx.master().fpwr_u8(station, kDigitalOutputs, kOutputPattern);
                     auto set = ctx.master().fprd_u8(station, kDigitalOutputs);
                     ctx.wait(kTarget * kLatePercent / 100);
                     auto after = ctx.master().fprd_u8(station, kDigitalOutputs);
                     return CaseResult::compare(fmt::format("0x0F00 0x{:02X} before, 0x00 after expiry", kOutputPattern),
                                                fmt::format("0x0F00 0x{:02X} before, 0x{:02X} after expiry", set ? *set : 0, after ? *after : 0xFFu));
                   }});
  return cases;
}

}  // namespace ecat::master::conformance
