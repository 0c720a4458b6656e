// ESM transitions, allowed and forbidden, with the AL status codes of
// ETG.1000.6 §6.4.1 / Table 11 (esm-al-codes.md §2, §4, §5).
#include <array>

#include "master/conformance/suite.hpp"

namespace ecat::master::conformance {

namespace {

constexpr std::uint16_t kInvalidStateChange = 0x0011;
constexpr std::uint16_t kUnknownState = 0x0012;
constexpr std::uint16_t kBootstrapNotSupported = 0x0013;
constexpr std::uint16_t kUnknownStateCode = 0x0005;  // not 1/2/3/4/8
constexpr std::uint16_t kPdiControlDeviceEmulation = 0x0100;  // SII word 0 high byte bit 0 = 0x0141 bit 0

// Device emulation (SII word 0 bit 8 -> 0x0141 bit 0): a slave without a µC
// (EK1100, EL1xxx) has the ESC copy AL control to AL status itself, so no
// application refuses a state, flags ErrInd or answers an acknowledge (ESC
// Section II 0x0140/0x0120): the cases built on a refusal do not apply.
bool device_emulation(Context& ctx) {
  return (ctx.info().sii.pdi_control & kPdiControlDeviceEmulation) != 0;
}
constexpr const char* kDeviceEmulationSkip =
    "device emulation: the ESC copies AL control to AL status, no application refuses a state";

std::string name_of(AlState s) {
  switch (s) {
    case AlState::Init: return "init";
    case AlState::PreOp: return "preop";
    case AlState::Boot: return "boot";
    case AlState::SafeOp: return "safeop";
    case AlState::Op: return "op";
  }
  return "?";
}

std::string expect_state(AlState s) {
  AlStatus st;
  st.raw = static_cast<std::uint8_t>(s);
  return format_status(st);
}

std::string expect_refused(AlState current, std::uint16_t code) {
  AlStatus st;
  st.raw = static_cast<std::uint16_t>(static_cast<std::uint8_t>(current) | kAlErrorBit);
  st.code = code;
  return format_status(st);
}

// Brings the slave to `from`, requests `to`, returns what the slave shows.
std::string transition(Context& ctx, AlState from, AlState to, std::string& setup_error) {
  if (auto r = ctx.go_to(from); !r) {
    setup_error = r.error();
    return {};
  }
  // What the master does before each upward transition (esm-al-codes.md §3).
  if (from == AlState::Init && to == AlState::PreOp && ctx.info().sii.has_mailbox()) {
    if (auto r = ctx.master().configure_mailbox(ctx.slave()); !r) {
      setup_error = std::string("mailbox SMs: ") + std::string(describe(r.error()));
      return {};
    }
  }
  if (from == AlState::PreOp && to == AlState::SafeOp) {
    if (auto r = ctx.prepare_process_data(); !r) {
      setup_error = r.error();
      return {};
    }
  }
  ctx.cycle();
  if (from == AlState::SafeOp && to == AlState::Op) ctx.run_until_sync0();
  auto st = ctx.master().request_state(ctx.slave(), to);
  if (!st) return std::string(describe(st.error()));
  return format_status(*st);
}

Case allowed(AlState from, AlState to, const char* code) {
  return Case{"esm." + name_of(from) + "_to_" + name_of(to),
              std::string("ETG.1000.6 §6.4.1 transition ") + code + " (allowed; esm-al-codes.md §2)",
              [from, to](Context& ctx) {
                std::string setup;
                std::string seen = transition(ctx, from, to, setup);
                if (!setup.empty()) return CaseResult::failed("reach " + expect_state(from), setup);
                return CaseResult::compare(expect_state(to), seen);
              }};
}

Case forbidden(AlState from, AlState to, std::uint16_t code) {
  return Case{"esm." + name_of(from) + "_to_" + name_of(to) + "_refused",
              "ETG.1000.6 §6.4.1, Table 11: AL status code " + hex(code, 4) + ", current state + ErrInd (esm-al-codes.md §2)",
              [from, to, code](Context& ctx) {
                if (device_emulation(ctx)) return CaseResult::skip(kDeviceEmulationSkip);
                std::string setup;
                std::string seen = transition(ctx, from, to, setup);
                if (!setup.empty()) return CaseResult::failed("reach " + expect_state(from), setup);
                return CaseResult::compare(expect_refused(from, code), seen);
              }};
}

}  // namespace

std::vector<Case> esm_cases() {
  using S = AlState;
  std::vector<Case> cases{
      allowed(S::Init, S::PreOp, "IP"),   allowed(S::PreOp, S::Init, "PI"),
      allowed(S::PreOp, S::SafeOp, "PS"), allowed(S::SafeOp, S::PreOp, "SP"),
      allowed(S::SafeOp, S::Init, "SI"),  allowed(S::SafeOp, S::Op, "SO"),
      allowed(S::Op, S::SafeOp, "OS"),    allowed(S::Op, S::PreOp, "OP"),
      allowed(S::Op, S::Init, "OI"),
      forbidden(S::Init, S::SafeOp, kInvalidStateChange),
      forbidden(S::Init, S::Op, kInvalidStateChange),
      forbidden(S::PreOp, S::Op, kInvalidStateChange),
      forbidden(S::PreOp, S::Boot, kInvalidStateChange),
      forbidden(S::SafeOp, S::Boot, kInvalidStateChange),
      forbidden(S::Op, S::Boot, kInvalidStateChange),
  };

  cases.push_back({"esm.init_to_boot", "ETG.1000.6 §6.4.1 IB, Table 11 0x0013 when Boot is not supported (esm-al-codes.md §2/§4)",
                   [](Context& ctx) {
                     if (device_emulation(ctx)) return CaseResult::skip(kDeviceEmulationSkip);
                     const auto& sii = ctx.info().sii;
                     if (sii.boot_rx_size != 0 && sii.boot_tx_size != 0) {
                       return CaseResult::skip("device supports Bootstrap (boot mailbox in SII)");
                     }
                     auto st = ctx.master().request_state(ctx.slave(), AlState::Boot);
                     return CaseResult::compare(expect_refused(AlState::Init, kBootstrapNotSupported),
                                                st ? format_status(*st) : std::string(describe(st.error())));
                   }});

  cases.push_back({"esm.unknown_state", "ETG.1000.6 Table 11: 0x0012 unknown requested state, current + ErrInd (esm-al-codes.md §1)",
                   [](Context& ctx) {
                     if (device_emulation(ctx)) return CaseResult::skip(kDeviceEmulationSkip);
                     if (auto r = ctx.go_to(AlState::PreOp); !r) return CaseResult::failed("reach PreOp", r.error());
                     auto st = ctx.master().write_al_control(ctx.slave(), kUnknownStateCode);
                     return CaseResult::compare(expect_refused(AlState::PreOp, kUnknownState),
                                                st ? format_status(*st) : std::string(describe(st.error())));
                   }});

  cases.push_back({"esm.error_acknowledge", "ETG.1000.6 §6.4.1: AL control bit 4 acknowledges ErrInd (esm-al-codes.md §5.3)",
                   [](Context& ctx) {
                     if (device_emulation(ctx)) return CaseResult::skip(kDeviceEmulationSkip);
                     auto refused = ctx.master().request_state(ctx.slave(), AlState::SafeOp);
                     if (!refused || !refused->error()) return CaseResult::failed("Init+E", "no refusal to acknowledge");
                     auto st = ctx.master().acknowledge_error(ctx.slave());
                     return CaseResult::compare("Init", st ? format_status(*st) : std::string(describe(st.error())));
                   }});

  cases.push_back({"esm.request_ignored_while_error",
                   "ETG.1000.6 §6.4.1: while ErrInd is set a request without acknowledge is not carried out (esm-al-codes.md §5.2)",
                   [](Context& ctx) {
                     // Device emulation (SII word 0 bit 8 -> 0x0141 bit 0): a slave without a
                     // µC (EK1100, EL1xxx) has the ESC copy AL control to AL status itself, so
                     // nothing holds a request back while ErrInd is set (ESC Section II 0x0140).
                     if (device_emulation(ctx)) return CaseResult::skip(kDeviceEmulationSkip);
                     auto refused = ctx.master().request_state(ctx.slave(), AlState::Op);
                     if (!refused || !refused->error()) return CaseResult::failed("Init+E", "no refusal");
                     if (ctx.info().sii.has_mailbox()) (void)ctx.master().configure_mailbox(ctx.slave());
                     auto st = ctx.master().request_state(ctx.slave(), AlState::PreOp);
                     return CaseResult::compare(expect_refused(AlState::Init, kInvalidStateChange),
                                                st ? format_status(*st) : std::string(describe(st.error())));
                   }});

  cases.push_back({"esm.ack_with_next_state", "ETG.1000.6 §6.4.1: acknowledge with a valid request performs it and clears 0x0134 (esm-al-codes.md §5.3)",
                   [](Context& ctx) {
                     if (device_emulation(ctx)) return CaseResult::skip(kDeviceEmulationSkip);
                     auto refused = ctx.master().request_state(ctx.slave(), AlState::Op);
                     if (!refused || !refused->error()) return CaseResult::failed("Init+E", "no refusal");
                     if (ctx.info().sii.has_mailbox()) (void)ctx.master().configure_mailbox(ctx.slave());
                     auto st = ctx.master().request_state(ctx.slave(), AlState::PreOp, true);
                     if (!st) return CaseResult::failed("PreOp", std::string(describe(st.error())));
                     // The code is cleared by the successful transition (esm-al-codes.md §5.3).
                     std::string seen = format_status(*st) + " code " + hex(st->code, 4);
                     return CaseResult::compare("PreOp code 0x0000", seen);
                   }});

  cases.push_back({"esm.status_reserved_bits", "ESC Section II p.34 (0x0130): bits 7:5 reserved 0; IgH compares the whole byte (masters.md §6 #10)",
                   [](Context& ctx) {
                     if (auto r = ctx.go_to(AlState::PreOp); !r) return CaseResult::failed("reach PreOp", r.error());
                     auto st = ctx.master().read_al_status(ctx.slave());
                     if (!st) return CaseResult::failed("0x02", std::string(describe(st.error())));
                     return CaseResult::compare(hex(0x02, 2), hex(st->raw & 0xFF, 2));
                   }});
  return cases;
}

}  // namespace ecat::master::conformance
