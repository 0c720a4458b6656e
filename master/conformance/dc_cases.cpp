// Distributed clocks and synchronisation: DC system time and delay
// plausibility (ESC Section II 0x0910-0x0934), 1C32h/1C33h sync modes and
// the AL codes of PreOp->SafeOp (ETG.1000.6 §5.6.7.4.3 / ETG.1020, Table 11
// 0x0027-0x0036), the SYNC unit's activation (0x0980-0x09A0), and SYNC0
// without frames (1C32h:0B, 10F1h:02, 0x001A). Sources as collected in
// shared/spec/esc-registers.md §10, coe-mailbox.md §11.3-§11.4,
// esm-al-codes.md §3-§4; the slave's own choices in docs/dc.md.
#include <fmt/format.h>

#include <cstdlib>

#include "common/frame.hpp"
#include "master/conformance/suite.hpp"
#include "master/registers.hpp"

namespace ecat::master::conformance {

namespace {

constexpr std::uint16_t kSmOutputParameter = 0x1C32;
constexpr std::uint16_t kSmInputParameter = 0x1C33;
constexpr std::uint8_t kSubSyncMode = 0x01;
constexpr std::uint8_t kSubCycleTime = 0x02;
constexpr std::uint8_t kSubModesSupported = 0x04;
constexpr std::uint8_t kSubMinCycle = 0x05;
constexpr std::uint8_t kSubSmEventMissed = 0x0B;
constexpr std::uint16_t kErrorSettings = 0x10F1;
constexpr std::uint8_t kSubSyncErrorLimit = 0x02;
// 1C32h:04 bits (coe-mailbox.md §11.3).
constexpr std::uint16_t kSupportsFreeRun = 0x0001;
constexpr std::uint16_t kSupportsDcMask = 0x000C;  // bits 3:2 = 01: DC
constexpr std::uint16_t kModeFreeRun = 0, kModeDcSync0 = 2;
// 1C32h:01 values.
// ETG.1000.6 Table 11 (esm-al-codes.md §4).
constexpr std::uint16_t kInvalidDcSync = 0x0030;
constexpr std::uint16_t kDcInvalidSyncCycle = 0x0035;
constexpr std::uint16_t kDcSync0Cycle = 0x0036;
constexpr std::uint16_t kSyncError = 0x001A;
constexpr std::uint32_t kAbortReadOnly = 0x06010002;  // CiA 301 / coe-mailbox.md §6: write to a read-only entry
// Marks a set-up the device cannot take because 1C32h:01 is read-only.
const std::string kReadOnlyMode = "read-only: ";
constexpr std::uint16_t kDcSpeedCounterDiff = 0x0932;
constexpr std::uint16_t kDcActivationStatus = 0x0984;
constexpr std::uint8_t kFirstSync0Pending = 0x01;     // 0x0984 bit 0
constexpr std::uint16_t kFeatureEnhancedSync = 0x0100;  // 0x0008 bit 8
constexpr std::uint32_t kDiffMagnitude = 0x7FFFFFFF;   // 0x092C bits 30:0
constexpr std::uint8_t kUnitAndSync0 = reg::kDcActivateCyclic | reg::kDcActivateSync0;
constexpr std::uint32_t kCycleNs = 1'000'000;  // SYNC0 cycle the cases use where the device allows it
constexpr Nanoseconds kStartDelay = std::chrono::milliseconds(20);
constexpr Nanoseconds kTimeWait = std::chrono::milliseconds(10);
// Plausibility bounds: system time advances with the master's time within
// 1 % + 100 µs; after configure_dc it is within 1 ms of the master's time;
// a propagation delay is below 1 ms; a settled time loop is within 1 µs.
constexpr std::int64_t kRatePermille = 10;
constexpr std::int64_t kSlackNs = 100'000;
constexpr std::int64_t kOffsetBoundNs = 1'000'000;
constexpr std::uint32_t kDelayBoundNs = 1'000'000;
constexpr std::uint32_t kSettledNs = 1'000;
constexpr unsigned kDriftIterations = 1000;
constexpr unsigned kRecheckIterations = 10;
constexpr unsigned kCyclesWithoutFrames = 10;
constexpr std::uint32_t kMissWeight = 3;
constexpr Nanoseconds kDefaultWatchdog = std::chrono::milliseconds(100);  // 0x0420 reset value

std::optional<CaseResult> need_dc(Context& ctx) {
  if (!ctx.info().esc.has_dc()) return CaseResult::skip("no DC (0x0008 bit 2 = 0)");
  return std::nullopt;
}

std::optional<CaseResult> need_dc_coe(Context& ctx) {
  if (auto c = need_dc(ctx)) return c;
  if (!ctx.info().sii.has_coe()) return CaseResult::skip("no CoE (no 1C32h)");
  return std::nullopt;
}

std::string shown(const Expected<AlStatus, MasterError>& st) { return st ? format_status(*st) : std::string(describe(st.error())); }

std::string refused(std::uint16_t code) {
  AlStatus s;
  s.raw = static_cast<std::uint16_t>(static_cast<std::uint8_t>(AlState::PreOp) | kAlErrorBit);
  s.code = code;
  return format_status(s);
}

Expected<std::uint64_t, std::string> read_u64(Context& ctx, std::uint16_t reg) {
  std::uint8_t b[8]{};
  if (auto r = ctx.master().fprd(ctx.info().station_address, reg, b); !r) return fail(fmt::format("FPRD {:#06x}: {}", reg, describe(r.error())));
  return load_le<std::uint64_t>(b);
}

Expected<void, std::string> configure_dc(Context& ctx) {
  if (auto r = ctx.master().configure_dc(ctx.master().clock().now()); !r) return fail("DC set-up: " + std::string(describe(r.error())));
  return {};
}

// The slave's 1C32h:01 and 1C33h:01, written back (when changed) and the SYNC
// unit switched off when a case is done, so later cases run free as before.
class SyncRestore {
 public:
  // In the suite's DC Sync0 mode the cases after this one run in DC: 2.
  explicit SyncRestore(Context& ctx) : ctx_(ctx) {
    CoeClient coe = ctx.coe();
    out_ = ctx.options().dc ? kModeDcSync0 : coe.upload_value(kSmOutputParameter, kSubSyncMode).value_or(kModeFreeRun);
    in_ = ctx.options().dc ? kModeDcSync0 : coe.upload_value(kSmInputParameter, kSubSyncMode).value_or(kModeFreeRun);
  }
  ~SyncRestore() {
    (void)ctx_.go_to(AlState::PreOp);
    (void)ctx_.master().fpwr_u8(ctx_.info().station_address, reg::kDcActivation, 0);
    CoeClient coe = ctx_.coe();
    for (auto [index, value] : {std::pair{kSmOutputParameter, out_}, std::pair{kSmInputParameter, in_}}) {
      auto now = coe.upload_value(index, kSubSyncMode);
      if (now && *now != value) (void)coe.download_value(index, kSubSyncMode, value, sizeof(std::uint16_t));
    }
  }
  SyncRestore(const SyncRestore&) = delete;
  SyncRestore& operator=(const SyncRestore&) = delete;

 private:
  Context& ctx_;
  std::uint32_t out_ = 0, in_ = 0;
};

// The SYNC unit programmed as masters do it (ETG.1020 §22.2, SOEM ecx_dcsync0;
// esc-registers.md §10): 0x0981 = 0, 0x09A0 = cycle, 0x0990 = system time +
// kStartDelay, then 0x0981 = activation (nothing more when 0), read back
// (Master::sync0_started).
Expected<std::uint64_t, std::string> program_sync(Context& ctx, std::uint32_t cycle, std::uint8_t activation) {
  const std::uint16_t station = ctx.info().station_address;
  auto w = [&](std::uint16_t reg, ConstBytes b) -> Expected<void, std::string> {
    if (auto r = ctx.master().fpwr(station, reg, b); !r) return fail(fmt::format("FPWR {:#06x}: {}", reg, describe(r.error())));
    return {};
  };
  if (activation == 0 && !ctx.info().esc.has_dc()) return 0;  // no SYNC unit to switch off
  const std::uint8_t off = 0;
  if (auto r = w(reg::kDcActivation, ConstBytes(&off, 1)); !r) return fail(r.error());
  if (activation == 0) return 0;
  std::uint8_t c[4];
  store_le(c, cycle);
  if (auto r = w(reg::kDcSync0CycleTime, c); !r) return fail(r.error());
  // A runner held up past kStartDelay before the activation (a loaded host,
  // a slow link) leaves the unit waiting for the wrap, and the case would
  // judge the device by the runner's delay: programmed again then, as
  // Master::configure_sync0 does (docs/master.md step 9).
  for (unsigned attempt = 0; attempt < Master::kSync0StartAttempts; ++attempt) {
    if (attempt > 0) {
      if (auto r = w(reg::kDcActivation, ConstBytes(&off, 1)); !r) return fail(r.error());
    }
    auto now = read_u64(ctx, reg::kDcSystemTime);
    if (!now) return fail(now.error());
    const std::uint64_t start = *now + static_cast<std::uint64_t>(kStartDelay.count());
    std::uint8_t t[8];
    store_le(t, start);
    if (auto r = w(reg::kDcStartTime, t); !r) return fail(r.error());
    if (auto r = w(reg::kDcActivation, ConstBytes(&activation, 1)); !r) return fail(r.error());
    auto started = ctx.master().sync0_started(ctx.slave());
    if (!started) return fail(fmt::format("SYNC0 start check: {}", describe(started.error())));
    if (*started) return start;
  }
  return fail(fmt::format("0x0990 read back behind 0x0910 after each of {} activations (the start time passed "
                          "before it, or 0x0990 does not read the next SYNC0)",
                          Master::kSync0StartAttempts));
}

// PreOp with process data, 1C32h:01 = `mode`, the SYNC unit with `cycle` and
// `activation`, then SafeOp requested: the AL status it gives.
Expected<AlStatus, std::string> safeop_with(Context& ctx, std::optional<std::uint16_t> mode, std::uint32_t cycle,
                                            std::uint8_t activation) {
  if (auto r = ctx.go_to(AlState::PreOp); !r) return fail("reach PreOp: " + r.error());
  if (ctx.options().dc) {
    // The suite's DC Sync0 mode programs SYNC0 in prepare_process_data; this case programs its own.
    SuiteOptions free = ctx.options();
    free.dc.reset();
    Context plain(ctx.master(), free);
    if (auto r = plain.prepare_process_data(); !r) return fail(r.error());
  } else if (auto r = ctx.prepare_process_data(); !r) {
    return fail(r.error());
  }
  CoeClient coe = ctx.coe();
  if (mode) {
    if (auto r = coe.download_value(kSmOutputParameter, kSubSyncMode, *mode, sizeof(std::uint16_t)); !r) {
      // SSC devices keep 1C32h:01 read-only and take the mode from 0x0981:
      // DC SYNC0 then needs no write; any other mode cannot be set.
      const bool follows_0981 = r.error().from_slave && static_cast<std::uint32_t>(r.error().code) == kAbortReadOnly;
      if (!(follows_0981 && *mode == kModeDcSync0 && (activation & reg::kDcActivateSync0) != 0)) {
        return fail((follows_0981 ? kReadOnlyMode : std::string()) + "1C32h:01 = " + std::to_string(*mode) + ": " + describe_sdo(r.error()));
      }
    }
  }
  // In DC mode 1C32h:02 is the SYNC0 cycle; a master writes it as it programs
  // 0x09A0 (coe-mailbox.md §11.3). Devices with a read-only 1C32h:02 refuse: fine.
  if ((activation & reg::kDcActivateSync0) != 0) (void)coe.download_value(kSmOutputParameter, kSubCycleTime, cycle, sizeof(std::uint32_t));
  if (auto r = configure_dc(ctx); !r) return fail(r.error());
  if (auto r = program_sync(ctx, cycle, activation); !r) return fail(r.error());
  auto st = ctx.master().request_state(ctx.slave(), AlState::SafeOp);
  if (!st) return fail("AL status: " + std::string(describe(st.error())));
  return *st;
}

Expected<std::uint32_t, std::string> sdo_u(Context& ctx, std::uint16_t index, std::uint8_t sub) {
  CoeClient coe = ctx.coe();
  auto v = coe.upload_value(index, sub);
  if (!v) return fail(fmt::format("{}:{:02X} {}", hex(index, 4), sub, describe_sdo(v.error())));
  return *v;
}

// 1C32h:04 with DC support, or the reason to skip.
Expected<std::uint16_t, CaseResult> dc_modes(Context& ctx) {
  if (auto c = need_dc_coe(ctx)) return fail(*c);
  if (auto r = ctx.go_to(AlState::PreOp); !r) return fail(CaseResult::failed("reach PreOp", r.error()));
  auto supported = sdo_u(ctx, kSmOutputParameter, kSubModesSupported);
  if (!supported) return fail(CaseResult::skip("no 1C32h:04 (" + supported.error() + ")"));
  if ((*supported & kSupportsDcMask) == 0) return fail(CaseResult::skip("1C32h:04 = " + hex(*supported, 4) + ": no DC sync mode"));
  return static_cast<std::uint16_t>(*supported);
}

CaseResult expect_refusal(Context& ctx, std::uint16_t code, std::optional<std::uint16_t> mode, std::uint32_t cycle, std::uint8_t activation) {
  SyncRestore restore(ctx);
  auto st = safeop_with(ctx, mode, cycle, activation);
  if (!st && st.error().starts_with(kReadOnlyMode)) {
    return CaseResult::skip("1C32h:01 is read-only (the mode follows 0x0981): this combination cannot be set (" +
                            st.error().substr(kReadOnlyMode.size()) + ")");
  }
  if (!st) return CaseResult::failed(refused(code), st.error());
  return CaseResult::compare(refused(code), format_status(*st));
}

CaseResult system_time_advances(Context& ctx) {
  if (auto c = need_dc(ctx)) return *c;
  if (!ctx.options().wait) return CaseResult::skip("no way to let time pass");
  if (auto r = configure_dc(ctx); !r) return CaseResult::failed("DC configured", r.error());
  const bool wide = (ctx.info().esc.features & EscInfo::kFeatureDc64) != 0;
  auto t1 = read_u64(ctx, reg::kDcSystemTime);
  const Nanoseconds m1 = ctx.master().clock().now();
  ctx.wait(kTimeWait);
  auto t2 = read_u64(ctx, reg::kDcSystemTime);
  const Nanoseconds m2 = ctx.master().clock().now();
  if (!t1 || !t2) return CaseResult::failed("0x0910 readable", t1 ? t2.error() : t1.error());
  const std::int64_t sys = wide ? static_cast<std::int64_t>(*t2 - *t1) : static_cast<std::int64_t>(static_cast<std::uint32_t>(*t2 - *t1));
  const std::int64_t master = (m2 - m1).count();
  const std::int64_t bound = master * kRatePermille / 1000 + kSlackNs;
  const std::string want = fmt::format("0x0910 advances {} µs +- {} µs", master / 1000, bound / 1000);
  if (std::llabs(sys - master) > bound) return CaseResult::failed(want, fmt::format("0x0910 advanced {} ns", sys));
  return CaseResult::pass(want, fmt::format("0x0910 advanced {} ns", sys));
}

CaseResult system_time_matches_master(Context& ctx) {
  if (auto c = need_dc(ctx)) return *c;
  if (auto r = configure_dc(ctx); !r) return CaseResult::failed("DC configured", r.error());
  ctx.wait(std::chrono::milliseconds(1));
  auto t = read_u64(ctx, reg::kDcSystemTime);
  if (!t) return CaseResult::failed("0x0910 readable", t.error());
  const bool wide = (ctx.info().esc.features & EscInfo::kFeatureDc64) != 0;
  const auto master = static_cast<std::uint64_t>(ctx.master().clock().now().count());
  const std::int64_t diff = wide ? static_cast<std::int64_t>(*t - master)
                                 : static_cast<std::int32_t>(static_cast<std::uint32_t>(*t) - static_cast<std::uint32_t>(master));
  const std::string want = fmt::format("0x0910 within {} µs of the master's time after 0x0920 was set", kOffsetBoundNs / 1000);
  if (std::llabs(diff) > kOffsetBoundNs) return CaseResult::failed(want, fmt::format("0x0910 - master = {} ns", diff));
  return CaseResult::pass(want, want);
}

CaseResult delay_and_offset(Context& ctx) {
  if (auto c = need_dc(ctx)) return *c;
  if (auto r = configure_dc(ctx); !r) return CaseResult::failed("DC configured", r.error());
  const auto& dc = ctx.info().dc;
  auto delay = ctx.master().fprd_u32(ctx.info().station_address, reg::kDcSystemTimeDelay);
  auto offset = read_u64(ctx, reg::kDcSystemTimeOffset);
  if (!delay || !offset) return CaseResult::failed("0x0920/0x0928 readable", "read failed");
  const bool wide = (ctx.info().esc.features & EscInfo::kFeatureDc64) != 0;
  const std::uint64_t want_offset = wide ? static_cast<std::uint64_t>(dc.offset_ns) : static_cast<std::uint32_t>(dc.offset_ns);
  const std::uint64_t seen_offset = wide ? *offset : static_cast<std::uint32_t>(*offset);
  const std::string want = fmt::format("0x0928 = {} ns (< {} µs), 0x0920 = {}", dc.delay_ns, kDelayBoundNs / 1000, want_offset);
  const std::string seen = fmt::format("0x0928 = {} ns{}, 0x0920 = {}", *delay, *delay < kDelayBoundNs ? fmt::format(" (< {} µs)", kDelayBoundNs / 1000) : "", seen_offset);
  return CaseResult::compare(want, seen);
}

CaseResult time_loop_settles(Context& ctx) {
  if (auto c = need_dc(ctx)) return *c;
  if (auto r = configure_dc(ctx); !r) return CaseResult::failed("DC configured", r.error());
  if (ctx.master().reference_clock() == ctx.slave()) {
    return CaseResult::skip("the slave is the reference clock (first DC slave): no 0x0910 comparisons reach its time loop");
  }
  if (auto r = ctx.master().fpwr_u16(ctx.info().station_address, reg::kDcSpeedCounterStart, 0x1000); !r) {
    return CaseResult::failed("0x0930 written", std::string(describe(r.error())));
  }
  auto diff0 = ctx.master().fprd_u32(ctx.info().station_address, reg::kDcSystemTimeDifference);
  auto speed0 = ctx.master().fprd_u16(ctx.info().station_address, kDcSpeedCounterDiff);
  if (auto r = ctx.master().dc_static_drift_compensation(kDriftIterations); !r) {
    return CaseResult::failed("drift compensation", std::string(describe(r.error())));
  }
  // The learned rate holds without comparisons for a while (the cycle of a
  // master that pauses); a few comparisons then find the clock still in step.
  ctx.wait(kTimeWait);
  if (auto r = ctx.master().dc_static_drift_compensation(kRecheckIterations); !r) {
    return CaseResult::failed("drift compensation", std::string(describe(r.error())));
  }
  auto diff = ctx.master().fprd_u32(ctx.info().station_address, reg::kDcSystemTimeDifference);
  if (!diff0 || !speed0 || !diff) return CaseResult::failed("0x092C/0x0932 readable", "read failed");
  const std::string want = fmt::format("0x092C/0x0932 = 0/0 after a 0x0930 write; |0x092C| < {} ns after {} FRMW", kSettledNs,
                                       kDriftIterations + kRecheckIterations);
  const std::uint32_t settled = *diff & kDiffMagnitude;
  const std::string seen = fmt::format("0x092C/0x0932 = {}/{} after a 0x0930 write; |0x092C| = {} ns after {} FRMW",
                                       *diff0 & kDiffMagnitude, *speed0, settled, kDriftIterations + kRecheckIterations);
  const bool ok = (*diff0 & kDiffMagnitude) == 0 && *speed0 == 0 && settled < kSettledNs;
  return ok ? CaseResult::pass(want, seen) : CaseResult::failed(want, seen);
}


CaseResult sync0_below_minimum(Context& ctx) {
  auto modes = dc_modes(ctx);
  if (!modes) return modes.error();
  auto min = sdo_u(ctx, kSmOutputParameter, kSubMinCycle);
  if (!min || *min < 2) return CaseResult::skip("no usable 1C32h:05 minimum cycle time");
  const std::uint32_t below = *min / 2;
  auto r = expect_refusal(ctx, kDcSync0Cycle, kModeDcSync0, below, kUnitAndSync0);
  // 0x0035 (invalid sync cycle time) names the same fault less precisely.
  if (r.verdict == Verdict::Fail && r.seen == refused(kDcInvalidSyncCycle)) r.verdict = Verdict::Pass;
  r.expected += fmt::format(" (or {}) for SYNC0 {} ns < 1C32h:05 {} ns", refused(kDcInvalidSyncCycle), below, *min);
  return r;
}

CaseResult sync0_at_minimum(Context& ctx) {
  auto modes = dc_modes(ctx);
  if (!modes) return modes.error();
  auto min = sdo_u(ctx, kSmOutputParameter, kSubMinCycle);
  if (!min) return CaseResult::skip("no 1C32h:05 (" + min.error() + ")");
  const std::uint32_t cycle = std::max(*min, kCycleNs);
  SyncRestore restore(ctx);
  auto st = safeop_with(ctx, kModeDcSync0, cycle, kUnitAndSync0);
  const std::string want = fmt::format("SafeOp with SYNC0 {} ns (1C32h:05 = {} ns)", cycle, *min);
  if (!st) return CaseResult::failed(want, st.error());
  return CaseResult::compare(want, fmt::format("{} with SYNC0 {} ns (1C32h:05 = {} ns)", format_status(*st), cycle, *min));
}

CaseResult sync_activation_sequence(Context& ctx) {
  if (auto c = need_dc(ctx)) return *c;
  if (!ctx.options().wait) return CaseResult::skip("no way to let time pass");
  SyncRestore restore(ctx);
  if (auto r = configure_dc(ctx); !r) return CaseResult::failed("DC configured", r.error());
  auto start = program_sync(ctx, kCycleNs, kUnitAndSync0);
  if (!start) return CaseResult::failed("SYNC0 set-up", start.error());
  const std::uint16_t station = ctx.info().station_address;
  const bool enhanced = (ctx.info().esc.features & kFeatureEnhancedSync) != 0;
  auto act = ctx.master().fprd_u8(station, reg::kDcActivation);
  auto cycle = ctx.master().fprd_u32(station, reg::kDcSync0CycleTime);
  auto pending = ctx.master().fprd_u8(station, kDcActivationStatus);
  ctx.wait(kStartDelay + 3 * Nanoseconds{kCycleNs});
  auto act_after = ctx.master().fprd_u8(station, reg::kDcActivation);
  auto pending_after = ctx.master().fprd_u8(station, kDcActivationStatus);
  auto next = read_u64(ctx, reg::kDcStartTime);
  if (!act || !cycle || !pending || !act_after || !pending_after || !next) return CaseResult::failed("0x0981/0x0984/0x0990/0x09A0 readable", "read failed");
  const bool wide = (ctx.info().esc.features & EscInfo::kFeatureDc64) != 0;
  const std::uint64_t from = wide ? *start : static_cast<std::uint32_t>(*start);
  const std::uint64_t at = wide ? *next : static_cast<std::uint32_t>(*next);
  const bool on_grid = at > from && (at - from) % kCycleNs == 0;
  auto show = [&](std::uint8_t a, std::uint32_t c, int p, std::uint8_t a2, int p2, bool grid) {
    return fmt::format("0x0981 {}, 0x09A0 {} ns{}; after the start 0x0981 {}{}, 0x0990 {}", hex(a, 2), c,
                       enhanced ? fmt::format(", 0x0984 bit 0 {}", p) : "", hex(a2, 2),
                       enhanced ? fmt::format(", 0x0984 bit 0 {}", p2) : "", grid ? "start + n x cycle" : "off the cycle grid");
  };
  return CaseResult::compare(show(kUnitAndSync0, kCycleNs, 1, kUnitAndSync0, 0, true),
                             show(*act, *cycle, *pending & kFirstSync0Pending, *act_after, *pending_after & kFirstSync0Pending, on_grid));
}

CaseResult sync0_without_frames(Context& ctx) {
  auto modes = dc_modes(ctx);
  if (!modes) return modes.error();
  if (!ctx.options().wait) return CaseResult::skip("no way to let time pass");
  auto limit = sdo_u(ctx, kErrorSettings, kSubSyncErrorLimit);
  if (!limit) return CaseResult::skip("no 10F1h:02 sync error counter limit (" + limit.error() + ")");
  if (*limit == 0) return CaseResult::skip("10F1h:02 = 0: the device does not detect sync errors");
  auto min = sdo_u(ctx, kSmOutputParameter, kSubMinCycle);
  const std::uint32_t cycle = std::max(min.value_or(0), kCycleNs);
  SyncRestore restore(ctx);
  {
    CoeClient coe = ctx.coe();
    auto w = coe.download_value(kSmOutputParameter, kSubSyncMode, kModeDcSync0, sizeof(std::uint16_t));
    // Read-only (SSC): the mode follows 0x0981, which the DC set-up activates.
    if (!w && !(w.error().from_slave && static_cast<std::uint32_t>(w.error().code) == kAbortReadOnly)) {
      return CaseResult::failed("1C32h:01 = 2 written", describe_sdo(w.error()));
    }
  }
  SuiteOptions dc = ctx.options();
  dc.dc = DcSync0{cycle, 0, "sync0_without_frames"};
  Context dctx(ctx.master(), dc);
  if (auto r = dctx.go_to(AlState::Op); !r) return CaseResult::failed("reach Op in DC Sync0 mode", r.error());
  // +3 per missed SM event (ETG.1020 / SSC), so limit / 3 + a margin of misses.
  const std::uint32_t misses = *limit / kMissWeight + kCyclesWithoutFrames;
  if (Nanoseconds{cycle} * misses >= kDefaultWatchdog) {
    return CaseResult::skip(fmt::format("10F1h:02 = {} needs {} SYNC0 cycles, beyond the process-data watchdog", *limit, misses));
  }
  ctx.wait(Nanoseconds{cycle} * misses);
  auto st = ctx.master().read_al_status(ctx.slave());
  auto missed = sdo_u(ctx, kSmOutputParameter, kSubSmEventMissed);
  if (!missed) missed = 1;  // 1C32h:0B is optional: the AL code alone tells
  AlStatus want;
  want.raw = static_cast<std::uint16_t>(static_cast<std::uint8_t>(AlState::SafeOp) | kAlErrorBit);
  want.code = kSyncError;
  const std::string expected = fmt::format("{}, 1C32h:0B > 0 after {} SYNC0 without frames (10F1h:02 = {})", format_status(want),
                                           misses, *limit);
  const std::string seen = fmt::format("{}, 1C32h:0B {} after {} SYNC0 without frames (10F1h:02 = {})", shown(st),
                                       *missed > 0 ? "> 0" : "= 0", misses, *limit);
  return CaseResult::compare(expected, seen);
}


}  // namespace

std::vector<Case> dc_cases() {
  std::vector<Case> cases;
  cases.push_back({"dc.system_time_advances", "ESC Section II 0x0910 (Section I §9.1): the system time advances with real time (10 ms within 1 % + 100 µs) (esc-registers.md §10)", system_time_advances});
  cases.push_back({"dc.system_time_matches_master", "ESC Section II 0x0910/0x0920: after the master set the offset from 0x0918, 0x0910 is within 1 ms of the master's time (esc-registers.md §10, masters.md DC)", system_time_matches_master});
  cases.push_back({"dc.delay_and_offset", "ESC Section II 0x0920/0x0928: offset and delay read back as written, delay below 1 ms (esc-registers.md §10)", delay_and_offset});
  cases.push_back({"dc.time_loop_settles", "ESC Section II 0x092C/0x0930/0x0932: a 0x0930 write resets 0x092C and 0x0932; after 1000 FRMW of 0x0910, 10 ms without and 10 more, |0x092C| < 1 µs (esc-registers.md §10)", time_loop_settles});
  cases.push_back({"dc.sync0_below_minimum_refused", "ETG.1000.6 Table 11 0x0036 (0x0035): SYNC0 cycle below 1C32h:05 refused at PreOp->SafeOp, PreOp + ErrInd (esm-al-codes.md §3-§4, coe-mailbox.md §11.3)", sync0_below_minimum});
  cases.push_back({"dc.sync0_minimum_accepted", "ETG.1000.6 §6.4.1 PreOp->SafeOp with 1C32h:01 = 2 and SYNC0 at max(1C32h:05, 1 ms): accepted (coe-mailbox.md §11.3)", sync0_at_minimum});
  cases.push_back({"dc.sync_mode_without_sync0_refused", "ETG.1000.6 Table 11 0x0030: 1C32h:01 = 2 (DC SYNC0) with the SYNC unit off (0x0981 = 0) refused, PreOp + ErrInd (esm-al-codes.md §3)",
                   [](Context& ctx) {
                     auto modes = dc_modes(ctx);
                     if (!modes) return modes.error();
                     return expect_refusal(ctx, kInvalidDcSync, kModeDcSync0, kCycleNs, 0);
                   }});
  cases.push_back({"dc.free_run_with_sync0_refused", "ETG.1000.6 Table 11 0x0030: 1C32h:01 = 0 (free run) while the SYNC unit generates SYNC0 refused, PreOp + ErrInd (esm-al-codes.md §3; SOES)",
                   [](Context& ctx) {
                     auto modes = dc_modes(ctx);
                     if (!modes) return modes.error();
                     if ((*modes & kSupportsFreeRun) == 0) return CaseResult::skip("1C32h:04 without free run");
                     return expect_refusal(ctx, kInvalidDcSync, kModeFreeRun, kCycleNs, kUnitAndSync0);
                   }});
  cases.push_back({"dc.single_shot_refused", "ETG.1000.6 Table 11 0x0035: DC SYNC0 mode with SYNC0 cycle 0 (single shot, 0x09A0 = 0) refused, PreOp + ErrInd (esm-al-codes.md §4)",
                   [](Context& ctx) {
                     auto modes = dc_modes(ctx);
                     if (!modes) return modes.error();
                     return expect_refusal(ctx, kDcInvalidSyncCycle, kModeDcSync0, 0, kUnitAndSync0);
                   }});
  cases.push_back({"dc.activation_sequence", "ESC Section II 0x0981/0x0984/0x0990/0x09A0: 0x0981 = 0, cycle, start time, 0x0981 = 3 -> active, first SYNC0 pending until the start, then 0x0990 = start + n x cycle (esc-registers.md §10, masters.md DC)", sync_activation_sequence});
  cases.push_back({"dc.sync0_without_frames", "ETG.1020 / ETG.1000.6 Table 11 0x001A: in DC Op, SYNC0 without new outputs counts 1C32h:0B and past 10F1h:02 drops to SafeOp + ErrInd 0x001A (coe-mailbox.md §11.3-§11.4, esm-al-codes.md §4)", sync0_without_frames});
  return cases;
}

}  // namespace ecat::master::conformance
