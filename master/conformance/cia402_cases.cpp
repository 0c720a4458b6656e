// CiA 402 drive behaviour (CiA 402-2 / IEC 61800-7-201 §8.1 power drive
// system FSA, §8.4 objects; no shared/spec file covers CiA 402: the
// statusword/controlword tables are CiA 402-2 Table 30 as docs/ds402.md
// lists them). Every case skips, with the device's SDO answer, when the
// device has no 6040h/6041h.
#include <algorithm>
#include <cstdlib>

#include "master/conformance/cia402_axis.hpp"
#include "master/conformance/suite.hpp"

namespace ecat::master::conformance {

namespace {

using cia402::State;

constexpr unsigned kRefusedCycles = 20;  // a refused command must still be refused after this many cycles

// One transition: reach `from`, send `cw`, expect `to`.
Case transition(std::string name, std::string clause, State from, std::uint16_t cw, State to) {
  return {std::move(name), std::move(clause), [from, cw, to](Context& ctx) {
            Cia402Axis axis(ctx);
            if (auto c = axis.open()) return *c;
            if (auto r = axis.reach(from); !r) return CaseResult::failed("reach " + cia402::name(from), r.error());
            return CaseResult::compare(cia402::name(to), cia402::name(axis.command_until(cw, to)));
          }};
}

// A command the FSA has no transition for in `from`: the state stays.
Case refused(std::string name, std::string clause, State from, std::uint16_t cw) {
  return {std::move(name), std::move(clause), [from, cw](Context& ctx) {
            Cia402Axis axis(ctx);
            if (auto c = axis.open()) return *c;
            if (from != State::SwitchOnDisabled) {
              if (auto r = axis.reach(from); !r) return CaseResult::failed("reach " + cia402::name(from), r.error());
            }
            axis.command(cw);
            axis.run(kRefusedCycles);
            return CaseResult::compare(cia402::name(from), cia402::name(axis.state()));
          }};
}

// Quick stop option code 605Ah (CiA 402-2 §8.4.1): 0..4 end in Switch on
// disabled (transition 12 follows 11), 5..8 stay in Quick stop active.
State quick_stop_end(std::int64_t option) {
  return option >= 5 && option <= 8 ? State::QuickStopActive : State::SwitchOnDisabled;
}

// Puts 605Ah to 6 (stop on the quick-stop ramp and stay in Quick stop
// active), drives to Quick stop active; nullopt on success.
std::optional<CaseResult> into_quick_stop_active(Cia402Axis& axis) {
  constexpr std::uint32_t kStayOnQuickStopRamp = 6;
  if (auto r = axis.change(cia402::kQuickStopOption, 0, kStayOnQuickStopRamp, 2); !r) {
    return CaseResult::skip("605Ah = 6 (stay in Quick stop active) not accepted: " + describe_sdo(r.error()));
  }
  if (auto r = axis.enable(); !r) return CaseResult::failed("reach Operation enabled", r.error());
  if (auto s = axis.command_until(cia402::kQuickStop, State::QuickStopActive); s != State::QuickStopActive) {
    return CaseResult::failed("Quick stop active (605Ah = 6)", cia402::name(s));
  }
  return std::nullopt;
}

// A reserved option code value (CiA 402-2 §8.4.1 605Ah-605Eh: 7FFFh lies in
// every option's reserved range) is refused with a value-range abort.
Case reserved_option(std::string name, std::uint16_t index) {
  return {std::move(name),
          "CiA 402-2 §8.4.1 " + hex(index, 4).substr(2) + "h option code: reserved value 7FFFh refused (CiA 301 abort 0609003xh; shared/spec/coe-mailbox.md abort codes)",
          [index](Context& ctx) {
            Cia402Axis axis(ctx);
            if (auto c = axis.open()) return *c;
            CoeClient coe = ctx.coe();
            auto old = coe.upload_value(index, 0);
            if (!old) return CaseResult::skip("no " + hex(index, 4) + ": " + describe_sdo(old.error()));
            constexpr std::uint32_t kReserved = 0x7FFF;
            auto r = coe.download_value(index, 0, kReserved, 2);
            if (r) {
              (void)coe.download_value(index, 0, *old, 2);
              return CaseResult::failed("abort 0x0609003x", "7FFFh accepted");
            }
            const std::string seen = describe_sdo(r.error());
            const bool range = seen.rfind("abort 0x0609003", 0) == 0;
            return range ? CaseResult::pass("abort 0x0609003x", seen) : CaseResult::failed("abort 0x0609003x", seen);
          }};
}

// Raises a following-error fault the way a master can on any drive with
// CSP: a following error window of 1 unit, timeout 0, and a set point far
// from the actual position (CiA 402-2 §12.4.2 6065h/6066h).
std::optional<CaseResult> provoke_fault(Cia402Axis& axis) {
  auto modes = axis.supported_modes();
  if (!modes || (*modes & (1u << (cia402::kCsp - 1))) == 0) {
    return CaseResult::skip("6502h lists no cyclic synchronous position mode to provoke a following error in");
  }
  if (!axis.mapped_out(cia402::kTargetPosition)) return CaseResult::skip("607Ah is not in the process data");
  if (axis.select_mode(cia402::kCsp) != cia402::kCsp) return CaseResult::failed("6061h = 8", "mode not taken");
  auto pos = axis.get(cia402::kPositionActual, 4);
  if (!pos) return CaseResult::failed("6064h readable", describe_sdo(pos.error()));
  (void)axis.set(cia402::kTargetPosition, *pos, 4);
  if (auto r = axis.enable(); !r) return CaseResult::failed("reach Operation enabled", r.error());
  // The tight window only once enabled at rest on the actual position.
  if (auto r = axis.change(cia402::kFollowingErrorWindow, 0, 1, 4); !r) {
    return CaseResult::skip("6065h following error window not writable: " + describe_sdo(r.error()));
  }
  if (auto r = axis.change(cia402::kFollowingErrorTimeout, 0, 0, 2); !r) {
    return CaseResult::skip("6066h following error timeout not writable: " + describe_sdo(r.error()));
  }
  constexpr std::int64_t kJump = 1'000'000;
  (void)axis.set(cia402::kTargetPosition, *pos + kJump, 4);
  State s = axis.state();
  for (unsigned i = 0; i < Cia402Axis::kMaxCycles && s != State::Fault; ++i) {
    axis.run(1);
    s = axis.state();
  }
  if (s != State::Fault) return CaseResult::failed("Fault after a following error", cia402::name(s));
  axis.command(cia402::kDisableVoltage);
  axis.run(2);
  return std::nullopt;
}

std::optional<RawEmergency> emergency_with(const Cia402Axis& axis, std::uint16_t code) {
  for (const auto& e : axis.emergencies()) {
    if (e.code() == code) return e;
  }
  return std::nullopt;
}

// Cyclic synchronous mode run: enables in `mode`, sends `setpoint(k)` each
// cycle over process data and returns "" or what went wrong.
template <typename Setpoint, typename Check>
CaseResult cyclic(Context& ctx, std::int8_t mode, std::uint16_t target, std::size_t target_bytes,
                  Setpoint setpoint, Check check) {
  Cia402Axis axis(ctx);
  if (auto c = axis.open()) return *c;
  auto modes = axis.supported_modes();
  if (!modes || (*modes & (1u << (mode - 1))) == 0) {
    return CaseResult::skip("6502h does not list mode " + std::to_string(mode));
  }
  if (!axis.mapped_out(target)) return CaseResult::skip(hex(target, 4) + " is not in the process data");
  if (!axis.mapped_out(cia402::kControlword) || !axis.mapped_in(cia402::kStatusword)) {
    return CaseResult::skip("6040h/6041h are not in the process data");
  }
  if (auto m = axis.select_mode(mode); m != mode) {
    return CaseResult::failed("6061h = " + std::to_string(mode), "6061h = " + std::to_string(m));
  }
  (void)axis.set(target, setpoint(axis, 0), target_bytes);
  if (auto r = axis.enable(); !r) return CaseResult::failed("reach Operation enabled", r.error());
  constexpr unsigned kCycles = 200;
  for (unsigned k = 1; k <= kCycles; ++k) {
    (void)axis.set(target, setpoint(axis, k), target_bytes);
    axis.run(1);
    const std::uint16_t sw = axis.statusword();
    if (cia402::decode(sw) != State::OperationEnabled || (sw & cia402::kBitFollowsCommand) == 0 ||
        (sw & cia402::kBitFollowingError) != 0) {
      return CaseResult::failed("Operation enabled, bit 12 set, bit 13 clear every cycle",
                                "cycle " + std::to_string(k) + ": statusword " + hex(sw, 4));
    }
  }
  return check(axis);
}

// 603Fh is answered "object does not exist" by a drive without it (the
// error code then lives in vendor objects only): the cases on 603Fh skip.
bool no_error_code(const Expected<std::int64_t, SdoError>& code) {
  return !code && code.error().from_slave && code.error().code == SdoAbortCode::ObjectNotFound;
}
constexpr const char* kNoErrorCode = "the device has no 603Fh error code (abort 06020000)";
}  // namespace


std::vector<Case> cia402_cases() {
  std::vector<Case> cases;
  const std::string fsa = "CiA 402-2 §8.1.3 Figure/Table 30 (IEC 61800-7-201) PDS FSA ";
  cases.push_back({"cia402.startup_switch_on_disabled", fsa + "transitions 0+1: Switch on disabled after start-up (statusword xxxx xxxx x1xx 0000)",
                   [](Context& ctx) {
                     Cia402Axis axis(ctx);
                     if (auto c = axis.open()) return *c;
                     axis.run(2);
                     return CaseResult::compare(cia402::name(State::SwitchOnDisabled), cia402::name(axis.state()));
                   }});
  cases.push_back(transition("cia402.t2_shutdown", fsa + "transition 2: shutdown (0006h) -> Ready to switch on (x01x 0001)",
                             State::SwitchOnDisabled, cia402::kShutdown, State::ReadyToSwitchOn));
  cases.push_back(transition("cia402.t3_switch_on", fsa + "transition 3: switch on (0007h) -> Switched on (x01x 0011)",
                             State::ReadyToSwitchOn, cia402::kSwitchOn, State::SwitchedOn));
  cases.push_back(transition("cia402.t4_enable_operation", fsa + "transition 4: enable operation (000Fh) -> Operation enabled (x01x 0111)",
                             State::SwitchedOn, cia402::kEnableOperation, State::OperationEnabled));
  cases.push_back(transition("cia402.t5_disable_operation", fsa + "transition 5: disable operation (0007h) -> Switched on",
                             State::OperationEnabled, cia402::kSwitchOn, State::SwitchedOn));
  cases.push_back(transition("cia402.t6_shutdown_from_switched_on", fsa + "transition 6: shutdown -> Ready to switch on",
                             State::SwitchedOn, cia402::kShutdown, State::ReadyToSwitchOn));
  cases.push_back(transition("cia402.t7_disable_voltage_from_ready", fsa + "transition 7: disable voltage (0000h) -> Switch on disabled",
                             State::ReadyToSwitchOn, cia402::kDisableVoltage, State::SwitchOnDisabled));
  cases.push_back(transition("cia402.t7_quick_stop_from_ready", fsa + "transition 7: quick stop (0002h) -> Switch on disabled",
                             State::ReadyToSwitchOn, cia402::kQuickStop, State::SwitchOnDisabled));
  cases.push_back(transition("cia402.t8_shutdown_from_enabled", fsa + "transition 8: shutdown from Operation enabled -> Ready to switch on",
                             State::OperationEnabled, cia402::kShutdown, State::ReadyToSwitchOn));
  cases.push_back(transition("cia402.t9_disable_voltage_from_enabled", fsa + "transition 9: disable voltage from Operation enabled -> Switch on disabled",
                             State::OperationEnabled, cia402::kDisableVoltage, State::SwitchOnDisabled));
  cases.push_back(transition("cia402.t10_disable_voltage_from_switched_on", fsa + "transition 10: disable voltage from Switched on -> Switch on disabled",
                             State::SwitchedOn, cia402::kDisableVoltage, State::SwitchOnDisabled));
  cases.push_back(transition("cia402.t10_quick_stop_from_switched_on", fsa + "transition 10: quick stop from Switched on -> Switch on disabled",
                             State::SwitchedOn, cia402::kQuickStop, State::SwitchOnDisabled));
  cases.push_back({"cia402.t11_quick_stop_per_605a", fsa + "transitions 11/12 with 605Ah (§8.4.1): option 0-4 end in Switch on disabled, 5-8 stay in Quick stop active",
                   [](Context& ctx) {
                     Cia402Axis axis(ctx);
                     if (auto c = axis.open()) return *c;
                     CoeClient coe = ctx.coe();
                     constexpr std::int64_t kDefaultQuickStop = 2;  // CiA 402-2 605Ah default
                     auto opt = coe.upload_value(cia402::kQuickStopOption, 0);
                     const std::int64_t option = opt ? static_cast<std::int16_t>(*opt) : kDefaultQuickStop;
                     if (auto r = axis.enable(); !r) return CaseResult::failed("reach Operation enabled", r.error());
                     const State want = quick_stop_end(option);
                     return CaseResult::compare(cia402::name(want),
                                                cia402::name(axis.command_until(cia402::kQuickStop, want)));
                   }});
  cases.push_back({"cia402.t12_disable_voltage_from_quick_stop", fsa + "transition 12: disable voltage in Quick stop active (605Ah = 6) -> Switch on disabled",
                   [](Context& ctx) {
                     Cia402Axis axis(ctx);
                     if (auto c = axis.open()) return *c;
                     if (auto c = into_quick_stop_active(axis)) return *c;
                     return CaseResult::compare(cia402::name(State::SwitchOnDisabled),
                                                cia402::name(axis.command_until(cia402::kDisableVoltage, State::SwitchOnDisabled)));
                   }});
  cases.push_back({"cia402.t16_enable_from_quick_stop", fsa + "transition 16: enable operation in Quick stop active (605Ah = 6) -> Operation enabled",
                   [](Context& ctx) {
                     Cia402Axis axis(ctx);
                     if (auto c = axis.open()) return *c;
                     if (auto c = into_quick_stop_active(axis)) return *c;
                     return CaseResult::compare(cia402::name(State::OperationEnabled),
                                                cia402::name(axis.command_until(cia402::kEnableOperation, State::OperationEnabled)));
                   }});
  cases.push_back(refused("cia402.refused_switch_on_from_disabled", fsa + "no transition from Switch on disabled on switch on (0007h)",
                          State::SwitchOnDisabled, cia402::kSwitchOn));
  cases.push_back(refused("cia402.refused_enable_from_disabled", fsa + "no transition from Switch on disabled on enable operation (000Fh)",
                          State::SwitchOnDisabled, cia402::kEnableOperation));
  cases.push_back(refused("cia402.refused_fault_reset_without_fault", fsa + "fault reset (bit 7 edge) with no fault: transition 15 only leaves Fault",
                          State::ReadyToSwitchOn, static_cast<std::uint16_t>(cia402::kFaultReset | cia402::kShutdown)));
  cases.push_back({"cia402.t13_t14_fault_on_following_error", fsa + "transitions 13/14: a following error (6065h/6066h, §12.4.2) ends in Fault (x0xx 1000), 603Fh set",
                   [](Context& ctx) {
                     Cia402Axis axis(ctx);
                     if (auto c = axis.open()) return *c;
                     if (auto c = provoke_fault(axis)) return *c;
                     auto code = axis.get(cia402::kErrorCode, 2);
                     if (no_error_code(code)) {
                       return CaseResult::compare(cia402::name(State::Fault), cia402::name(axis.state()));
                     }
                     const std::string seen = cia402::name(axis.state()) + ", 603Fh " +
                                              (code ? (*code != 0 ? "set" : "0") : describe_sdo(code.error()));
                     return CaseResult::compare("Fault, 603Fh set", seen);
                   }});
  cases.push_back({"cia402.fault_refuses_enable", fsa + "no transition out of Fault but 15: enable operation (000Fh) leaves the drive in Fault",
                   [](Context& ctx) {
                     Cia402Axis axis(ctx);
                     if (auto c = axis.open()) return *c;
                     if (auto c = provoke_fault(axis)) return *c;
                     for (std::uint16_t cw : {cia402::kShutdown, cia402::kSwitchOn, cia402::kEnableOperation}) {
                       axis.command(cw);
                       axis.run(kRefusedCycles / 2);
                     }
                     return CaseResult::compare(cia402::name(State::Fault), cia402::name(axis.state()));
                   }});
  cases.push_back({"cia402.t15_fault_reset", fsa + "transition 15: fault reset (rising edge of bit 7) -> Switch on disabled, 603Fh = 0",
                   [](Context& ctx) {
                     Cia402Axis axis(ctx);
                     if (auto c = axis.open()) return *c;
                     if (auto c = provoke_fault(axis)) return *c;
                     const State s = axis.command_until(cia402::kFaultReset, State::SwitchOnDisabled);
                     auto code = axis.get(cia402::kErrorCode, 2);
                     if (no_error_code(code)) {
                       return CaseResult::compare(cia402::name(State::SwitchOnDisabled), cia402::name(s));
                     }
                     return CaseResult::compare(cia402::name(State::SwitchOnDisabled) + ", 603Fh 0x0000",
                                                cia402::name(s) + ", 603Fh " + (code ? hex(static_cast<std::uint32_t>(*code & 0xFFFF), 4) : "?"));
                   }});
  cases.push_back({"cia402.fault_emergency", "CiA 402-2 §8.4.11 603Fh / CiA 301 §7.2.7 EMCY / ETG.1000.6 §5.6.4 (shared/spec/coe-mailbox.md §9): the fault sends an emergency with 603Fh's code and 1001h",
                   [](Context& ctx) {
                     Cia402Axis axis(ctx);
                     if (auto c = axis.open()) return *c;
                     if (auto c = provoke_fault(axis)) return *c;
                     auto code = axis.get(cia402::kErrorCode, 2);
                     if (no_error_code(code)) return CaseResult::skip(kNoErrorCode);
                     if (!code) return CaseResult::failed("603Fh readable", describe_sdo(code.error()));
                     CoeClient coe = ctx.coe();
                     auto reg = coe.upload_value(cia402::kErrorRegister, 0);
                     const auto c16 = static_cast<std::uint16_t>(*code);
                     // CiA 301 §7.2.7.1: FF00h-FFFFh is "device specific"; drives such as
                     // Yaskawa's Σ-V send FF00h with the alarm in the manufacturer bytes.
                     constexpr std::uint16_t kDeviceSpecific = 0xFF00;
                     auto e = emergency_with(axis, c16);
                     if (!e) {
                       for (const auto& any : axis.emergencies()) {
                         if (any.code() >= kDeviceSpecific) e = any;
                       }
                     }
                     const std::string want = "EMCY " + hex(c16, 4) + " (or FFxxh) reg " + (reg ? hex(*reg, 2) : "?");
                     if (!e) return CaseResult::failed(want, std::to_string(axis.emergencies().size()) + " emergencies, none with the code");
                     const std::string code_seen = e->code() == c16 ? hex(c16, 4) + " (or FFxxh)" : hex(e->code(), 4);
                     const bool ok = reg && e->error_register() == *reg;
                     const std::string seen = "EMCY " + code_seen + " reg " + hex(e->error_register(), 2);
                     return ok ? CaseResult::pass(want, seen) : CaseResult::failed(want, seen);
                   }});
  cases.push_back({"cia402.fault_error_register_generic_bit", "CiA 301 §7.5.2.2 1001h: while the drive is in Fault the error register is non-zero with bit 0 (generic error) set",
                   [](Context& ctx) {
                     Cia402Axis axis(ctx);
                     if (auto c = axis.open()) return *c;
                     if (auto c = provoke_fault(axis)) return *c;
                     CoeClient coe = ctx.coe();
                     auto reg = coe.upload_value(cia402::kErrorRegister, 0);
                     if (!reg) return CaseResult::failed("1001h readable", describe_sdo(reg.error()));
                     constexpr std::uint32_t kGenericError = 0x01;
                     const std::string seen = "1001h " + hex(*reg, 2);
                     return (*reg & kGenericError) != 0 ? CaseResult::pass("1001h bit 0 set", seen)
                                                        : CaseResult::failed("1001h bit 0 set", seen);
                   }});
  cases.push_back({"cia402.fault_reset_emergency", "CiA 301 §7.2.7.1 (EMCY 0000h \"error reset\") / ETG.1000.6 §5.6.4 (shared/spec/coe-mailbox.md §9): a fault reset sends EMCY 0000h, 1001h = 0",
                   [](Context& ctx) {
                     Cia402Axis axis(ctx);
                     if (auto c = axis.open()) return *c;
                     if (auto c = provoke_fault(axis)) return *c;
                     (void)axis.command_until(cia402::kFaultReset, State::SwitchOnDisabled);
                     axis.run(2);
                     auto e = emergency_with(axis, 0x0000);
                     CoeClient coe = ctx.coe();
                     auto reg = coe.upload_value(cia402::kErrorRegister, 0);
                     return CaseResult::compare("EMCY 0000h, 1001h 0x00",
                                                std::string(e ? "EMCY 0000h" : "no EMCY 0000h") + ", 1001h " +
                                                    (reg ? hex(*reg, 2) : describe_sdo(reg.error())));
                   }});
  cases.push_back({"cia402.modes_display_follows_6060", "CiA 402-2 §8.4.1/§8.4.2: 6061h shows every mode 6502h lists once 6060h selects it",
                   [](Context& ctx) {
                     Cia402Axis axis(ctx);
                     if (auto c = axis.open()) return *c;
                     auto modes = axis.supported_modes();
                     if (!modes) return CaseResult::skip("no 6502h supported drive modes");
                     std::string want, seen;
                     constexpr std::int8_t kLastStandardMode = 10;
                     for (std::int8_t m = 1; m <= kLastStandardMode; ++m) {
                       if ((*modes & (1u << (m - 1))) == 0) continue;
                       want += std::to_string(m) + " ";
                       seen += std::to_string(axis.select_mode(m)) + " ";
                     }
                     if (want.empty()) return CaseResult::skip("6502h lists no standard mode");
                     return CaseResult::compare(want, seen);
                   }});
  cases.push_back({"cia402.mode_not_in_6502_refused", "CiA 402-2 §8.4.1/§8.4.3: a mode 6502h does not list is refused (abort 0609003xh) or never shown in 6061h",
                   [](Context& ctx) {
                     Cia402Axis axis(ctx);
                     if (auto c = axis.open()) return *c;
                     auto modes = axis.supported_modes();
                     if (!modes) return CaseResult::skip("no 6502h supported drive modes");
                     constexpr std::int8_t kLastStandardMode = 10;
                     std::int8_t absent = 0;
                     for (std::int8_t m = 1; m <= kLastStandardMode && absent == 0; ++m) {
                       if ((*modes & (1u << (m - 1))) == 0) absent = m;
                     }
                     if (absent == 0) return CaseResult::skip("6502h lists every standard mode 1-10");
                     const std::string want = "6061h not " + std::to_string(absent);
                     // Over process data when 6060h is mapped (the SDO value would be overwritten).
                     if (!axis.mapped_out(cia402::kModes)) {
                       CoeClient coe = ctx.coe();
                       if (auto r = coe.download_value(cia402::kModes, 0, static_cast<std::uint8_t>(absent), 1); !r) {
                         return CaseResult::pass(want, "6060h = " + std::to_string(absent) + " " + describe_sdo(r.error()));
                       }
                     } else {
                       (void)axis.set(cia402::kModes, absent, 1);
                     }
                     axis.run(10);
                     auto after = axis.get(cia402::kModesDisplay, 1);
                     const std::string seen = after ? "6061h " + std::to_string(*after) : describe_sdo(after.error());
                     return after && *after != absent ? CaseResult::pass(want, seen) : CaseResult::failed(want, seen);
                   }});
  cases.push_back({"cia402.csp_follows_set_point", "CiA 402-2 §13 (cyclic synchronous position): 607Ah over process data each cycle; Operation enabled, statusword bit 12 set, bit 13 clear; 6064h reaches the last set point within 6065h",
                   [](Context& ctx) {
                     std::int64_t start = 0;
                     constexpr std::int64_t kStep = 20;
                     constexpr unsigned kSettle = 200;
                     return cyclic(
                         ctx, cia402::kCsp, cia402::kTargetPosition, 4,
                         [&](Cia402Axis& axis, unsigned k) {
                           if (k == 0) {
                             auto p = axis.get(cia402::kPositionActual, 4);
                             start = p ? *p : 0;
                           }
                           return start + kStep * static_cast<std::int64_t>(std::min(k, 100u));
                         },
                         [&](Cia402Axis& axis) {
                           axis.run(kSettle / 4);
                           auto p = axis.get(cia402::kPositionActual, 4);
                           CoeClient coe = ctx.coe();
                           auto window = coe.upload_value(cia402::kFollowingErrorWindow, 0);
                           // 6065h = FFFFFFFFh switches the check off (§12.4.2): then 1000 units.
                           constexpr std::int64_t kDefaultTolerance = 1000;
                           const std::int64_t tol = window ? std::min<std::int64_t>(*window, kDefaultTolerance) : kDefaultTolerance;
                           const std::int64_t target = start + kStep * 100;
                           if (!p) return CaseResult::failed("6064h readable", describe_sdo(p.error()));
                           const std::string want = "6064h within " + std::to_string(tol) + " of " + std::to_string(target);
                           return std::llabs(*p - target) <= tol ? CaseResult::pass(want, "6064h " + std::to_string(*p))
                                                                 : CaseResult::failed(want, "6064h " + std::to_string(*p));
                         });
                   }});
  cases.push_back({"cia402.csv_follows_set_point", "CiA 402-2 §14 (cyclic synchronous velocity): 60FFh over process data each cycle; Operation enabled, bit 12 set, bit 13 clear; 606Ch reaches 60FFh within 10 %",
                   [](Context& ctx) {
                     constexpr std::int64_t kVelocity = 10'000;
                     return cyclic(
                         ctx, cia402::kCsv, cia402::kTargetVelocity, 4,
                         [](Cia402Axis&, unsigned k) { return k == 0 ? 0 : kVelocity; },
                         [](Cia402Axis& axis) {
                           auto v = axis.get(cia402::kVelocityActual, 4);
                           (void)axis.set(cia402::kTargetVelocity, 0, 4);
                           if (!v) return CaseResult::failed("606Ch readable", describe_sdo(v.error()));
                           const std::string want = "606Ch " + std::to_string(kVelocity) + " +- 10 %";
                           const bool ok = std::llabs(*v - kVelocity) <= kVelocity / 10;
                           return ok ? CaseResult::pass(want, "606Ch " + std::to_string(*v))
                                     : CaseResult::failed(want, "606Ch " + std::to_string(*v));
                         });
                   }});
  cases.push_back({"cia402.cst_follows_set_point", "CiA 402-2 §15 (cyclic synchronous torque): 6071h over process data each cycle; Operation enabled, bit 12 set, bit 13 clear; 6077h follows 6071h (sign and within 20 %)",
                   [](Context& ctx) {
                     constexpr std::int64_t kTorque = 50;  // per mille of the rated torque
                     return cyclic(
                         ctx, cia402::kCst, cia402::kTargetTorque, 2,
                         [](Cia402Axis&, unsigned k) { return k < 190 ? kTorque : -kTorque; },
                         [](Cia402Axis& axis) {
                           auto t = axis.get(cia402::kTorqueActual, 2);
                           (void)axis.set(cia402::kTargetTorque, 0, 2);
                           if (!t) return CaseResult::failed("6077h readable", describe_sdo(t.error()));
                           const std::string want = "6077h " + std::to_string(-kTorque) + " +- 20 %";
                           const bool ok = std::llabs(*t + kTorque) <= kTorque / 5;
                           return ok ? CaseResult::pass(want, "6077h " + std::to_string(*t))
                                     : CaseResult::failed(want, "6077h " + std::to_string(*t));
                         });
                   }});
  cases.push_back(reserved_option("cia402.option_605a_reserved_refused", cia402::kQuickStopOption));
  cases.push_back(reserved_option("cia402.option_605b_reserved_refused", cia402::kShutdownOption));
  cases.push_back(reserved_option("cia402.option_605c_reserved_refused", cia402::kDisableOperationOption));
  cases.push_back(reserved_option("cia402.option_605d_reserved_refused", cia402::kHaltOption));
  cases.push_back(reserved_option("cia402.option_605e_reserved_refused", cia402::kFaultReactionOption));
  return cases;
}

// Pre-defined error field 1003h (CiA 301 §7.5.2.3), with the CiA 402 fault
// above as the error: the device signals it by EMCY and keeps it in 1003h.
namespace {

constexpr std::uint16_t kErrorField = 0x1003;
constexpr std::uint32_t kValueRange = 0x06090030;

std::optional<CaseResult> need_error_field(Context& ctx) {
  if (auto r = ctx.go_to(AlState::PreOp); !r) return CaseResult::failed("reach PreOp", r.error());
  if (!ctx.info().sii.has_coe()) return CaseResult::skip("no CoE");
  if (auto r = ctx.coe().upload_value(kErrorField, 0); !r) return CaseResult::skip("no 1003h: " + describe_sdo(r.error()));
  return std::nullopt;
}

std::optional<CaseResult> clear_error_field(Context& ctx) {
  const std::uint8_t zero[1]{0};
  if (auto w = ctx.coe().download(kErrorField, 0, zero); !w) return CaseResult::failed("1003h:00 = 0 taken", describe_sdo(w.error()));
  return std::nullopt;
}

}  // namespace

std::vector<Case> error_field_cases() {
  std::vector<Case> cases;
  cases.push_back({"emcy.1003h_records_error", "CiA 301 §7.5.2.3 1003h: after 1003h was cleared, the drive fault's emergency is kept: 1003h:00 = 1, 1003h:01 bits 0-15 = the EMCY error code",
                   [](Context& ctx) {
                     if (auto c = need_error_field(ctx)) return *c;
                     if (auto c = clear_error_field(ctx)) return *c;
                     Cia402Axis axis(ctx);
                     if (auto c = axis.open()) return *c;
                     if (auto c = provoke_fault(axis)) return *c;
                     axis.collect_emergencies();
                     const auto& all = axis.emergencies();
                     std::optional<std::uint16_t> code;
                     for (const auto& e : all) {
                       if (e.code() != 0) code = e.code();
                     }
                     if (!code) return CaseResult::failed("an EMCY for the fault", std::to_string(all.size()) + " emergencies, none with an error");
                     CoeClient coe = ctx.coe();
                     auto n = coe.upload_value(kErrorField, 0);
                     auto first = coe.upload_value(kErrorField, 1);
                     const std::string want = "1003h:00 = 1, 1003h:01 code " + hex(*code, 4);
                     if (!n || !first) return CaseResult::failed(want, describe_sdo(n ? first.error() : n.error()));
                     return CaseResult::compare(want, "1003h:00 = " + std::to_string(*n) + ", 1003h:01 code " + hex(*first & 0xFFFF, 4));
                   }});
  cases.push_back({"emcy.1003h_write_zero_clears", "CiA 301 §7.5.2.3 1003h: writing 0 to 1003h:00 deletes the error history (1003h:00 reads 0 after a fault filled it)",
                   [](Context& ctx) {
                     if (auto c = need_error_field(ctx)) return *c;
                     {
                       Cia402Axis axis(ctx);
                       if (auto c = axis.open()) return *c;
                       if (auto c = provoke_fault(axis)) return *c;
                     }
                     CoeClient coe = ctx.coe();
                     auto before = coe.upload_value(kErrorField, 0);
                     if (!before || *before == 0) return CaseResult::failed("1003h:00 > 0 after a fault", before ? "0" : describe_sdo(before.error()));
                     if (auto c = clear_error_field(ctx)) return *c;
                     auto after = coe.upload_value(kErrorField, 0);
                     return CaseResult::compare("1003h:00 = 0", after ? "1003h:00 = " + std::to_string(*after) : describe_sdo(after.error()));
                   }});
  cases.push_back({"emcy.1003h_write_nonzero_refused", "CiA 301 §7.5.2.3 1003h: a value other than 0 written to 1003h:00 is refused with SDO abort 06090030h",
                   [](Context& ctx) {
                     if (auto c = need_error_field(ctx)) return *c;
                     const std::uint8_t one[1]{1};
                     auto w = ctx.coe().download(kErrorField, 0, one);
                     return CaseResult::compare("abort " + hex(kValueRange, 8), w ? std::string("taken") : describe_sdo(w.error()));
                   }});
  return cases;
}

}  // namespace ecat::master::conformance
