// Diagnosis history 10F3h (ETG.1020 §13 "Diagnosis history"; the object as
// Beckhoff's and WAGO's manuals describe it, docs/coe.md "Diagnosis
// history": no shared/spec file covers ETG.1020). The emergency cases
// proper (format, 1001h, EMCY 0000h on reset) run with the CiA 402 fault in
// cia402_cases.cpp. A message is provoked the way any master can: a refused
// AL transition (PreOp -> Op, AL status code 0011h) - a device that logs
// nothing for it skips with that answer.
#include "master/conformance/suite.hpp"

namespace ecat::master::conformance {

namespace {

constexpr std::uint16_t kDiagHistory = 0x10F3;
constexpr std::uint8_t kMaxMessages = 1;
constexpr std::uint8_t kNewest = 2;
constexpr std::uint8_t kNewestAcknowledged = 3;
constexpr std::uint8_t kNewMessages = 4;
constexpr std::uint8_t kFlags = 5;
constexpr std::uint8_t kFirstMessage = 6;
constexpr std::uint16_t kFlagAcknowledgeMode = 0x0010;
constexpr std::size_t kMessageHeader = 4 + 2 + 2 + 8;  // diag code, flags, text ID, time stamp
constexpr std::uint16_t kTypeMask = 0x000F;
constexpr std::uint16_t kTypeError = 2;
constexpr unsigned kParameterShift = 8;

std::optional<CaseResult> need_history(Context& ctx) {
  if (auto r = ctx.go_to(AlState::PreOp); !r) return CaseResult::failed("reach PreOp", r.error());
  if (!ctx.info().sii.has_coe()) return CaseResult::skip("no CoE");
  CoeClient coe = ctx.coe();
  if (auto r = coe.upload_value(kDiagHistory, 0); !r) return CaseResult::skip("no 10F3h: " + describe_sdo(r.error()));
  return std::nullopt;
}

// Refuses PreOp -> Op (0x0011) and returns 10F3h:02 afterwards; the error is
// acknowledged back to PreOp.
Expected<std::uint32_t, std::string> provoke_message(Context& ctx) {
  Master& m = ctx.master();
  auto r = m.write_al_control(ctx.slave(), static_cast<std::uint16_t>(AlState::Op));
  if (!r) return fail("request Op: " + std::string(describe(r.error())));
  (void)m.request_state(ctx.slave(), AlState::PreOp, true);
  CoeClient coe = ctx.coe();
  auto newest = coe.upload_value(kDiagHistory, kNewest);
  if (!newest) return fail("10F3h:02 " + describe_sdo(newest.error()));
  return *newest;
}

// A new message after the refused transition; the case's reason otherwise.
std::optional<CaseResult> new_message(Context& ctx, std::uint32_t& newest) {
  CoeClient coe = ctx.coe();
  auto before = coe.upload_value(kDiagHistory, kNewest);
  if (!before) return CaseResult::failed("10F3h:02 readable", describe_sdo(before.error()));
  // Read the newest message first: a new one then shows in 10F3h:04.
  if (*before != 0) (void)coe.upload(kDiagHistory, static_cast<std::uint8_t>(*before));
  auto after = provoke_message(ctx);
  if (!after) return CaseResult::failed("message after AL status 0x0011", after.error());
  auto max = coe.upload_value(kDiagHistory, kMaxMessages);
  const std::uint32_t ring = max ? *max : 0;
  if (*after == *before && ring > 1) return CaseResult::skip("no diagnosis message for AL status code 0x0011 (10F3h:02 unchanged)");
  newest = *after;
  return std::nullopt;
}

}  // namespace

std::vector<Case> emergency_cases() {
  std::vector<Case> cases;
  cases.push_back({"diag.10f3_layout", "ETG.1020 §13 10F3h: subindex 0 = 5 + maximum messages (10F3h:01 >= 1); messages in subindices 6.. (docs/coe.md \"Diagnosis history\")",
                   [](Context& ctx) {
                     if (auto c = need_history(ctx)) return *c;
                     CoeClient coe = ctx.coe();
                     auto n = coe.upload_value(kDiagHistory, 0);
                     auto max = coe.upload_value(kDiagHistory, kMaxMessages);
                     if (!n || !max) return CaseResult::failed("10F3h:00/01 readable", describe_sdo(n ? max.error() : n.error()));
                     const std::string seen = "SI0 " + std::to_string(*n) + ", max " + std::to_string(*max);
                     const bool ok = *max >= 1 && *n == kFirstMessage - 1 + *max;
                     return ok ? CaseResult::pass("SI0 = 5 + max, max >= 1", seen) : CaseResult::failed("SI0 = 5 + max, max >= 1", seen);
                   }});
  cases.push_back({"diag.10f3_newest_message", "ETG.1020 §13 10F3h:02: after a new message the newest-message subindex lies in 6..SI0 and names a non-empty message",
                   [](Context& ctx) {
                     if (auto c = need_history(ctx)) return *c;
                     std::uint32_t newest = 0;
                     if (auto c = new_message(ctx, newest)) return *c;
                     CoeClient coe = ctx.coe();
                     auto n = coe.upload_value(kDiagHistory, 0);
                     if (!n) return CaseResult::failed("10F3h:00", describe_sdo(n.error()));
                     if (newest < kFirstMessage || newest > *n) {
                       return CaseResult::failed("10F3h:02 in 6.." + std::to_string(*n), "10F3h:02 " + std::to_string(newest));
                     }
                     auto msg = coe.upload(kDiagHistory, static_cast<std::uint8_t>(newest));
                     const std::string seen = msg ? (msg->empty() ? "empty message" : "message") : describe_sdo(msg.error());
                     return CaseResult::compare("message", seen);
                   }});
  cases.push_back({"diag.10f3_message_format", "ETG.1020 §13 diagnosis message: Diag Code UDINT, Flags UINT (type 0-2, parameter count in bits 8-15), Text ID UINT, Time Stamp ULINT, then the typed parameters; the length matches",
                   [](Context& ctx) {
                     if (auto c = need_history(ctx)) return *c;
                     std::uint32_t newest = 0;
                     if (auto c = new_message(ctx, newest)) return *c;
                     CoeClient coe = ctx.coe();
                     auto msg = coe.upload(kDiagHistory, static_cast<std::uint8_t>(newest));
                     if (!msg) return CaseResult::failed("message readable", describe_sdo(msg.error()));
                     const std::string want = "header of 16 bytes, type <= 2, parameters fill the rest";
                     if (msg->size() < kMessageHeader) return CaseResult::failed(want, std::to_string(msg->size()) + " bytes");
                     const auto flags = load_le<std::uint16_t>(msg->data() + 4);
                     const unsigned params = flags >> kParameterShift;
                     std::size_t at = kMessageHeader;
                     for (unsigned p = 0; p < params && at + 2 <= msg->size(); ++p) {
                       const auto type = load_le<std::uint16_t>(msg->data() + at);
                       at += 2;
                       switch (type) {
                         case 0x0001: case 0x0002: case 0x0005: at += 1; break;  // BOOL, INT8, UINT8
                         case 0x0003: case 0x0006: at += 2; break;               // INT16, UINT16
                         case 0x0004: case 0x0007: case 0x0008: at += 4; break;  // INT32, UINT32, REAL32
                         default: return CaseResult::pass(want, "parameter type " + hex(type, 4) + " not checked");
                       }
                     }
                     const std::string seen = "type " + std::to_string(flags & kTypeMask) + ", " + std::to_string(params) +
                                              " parameters, " + std::to_string(msg->size()) + " bytes (" + std::to_string(at) + " expected)";
                     const bool ok = (flags & kTypeMask) <= kTypeError && at == msg->size() &&
                                     load_le<std::uint32_t>(msg->data()) != 0;
                     return ok ? CaseResult::pass(want, seen) : CaseResult::failed(want, seen);
                   }});
  cases.push_back({"diag.10f3_new_messages_flag", "ETG.1020 §13 10F3h:04 (overwrite mode): 1 after a new message, 0 once the newest message was read (docs/coe.md)",
                   [](Context& ctx) {
                     if (auto c = need_history(ctx)) return *c;
                     CoeClient coe = ctx.coe();
                     auto flags = coe.upload_value(kDiagHistory, kFlags);
                     if (flags && (*flags & kFlagAcknowledgeMode) != 0) return CaseResult::skip("10F3h:05 acknowledge mode set");
                     std::uint32_t newest = 0;
                     if (auto c = new_message(ctx, newest)) return *c;
                     auto set = coe.upload_value(kDiagHistory, kNewMessages);
                     (void)coe.upload(kDiagHistory, static_cast<std::uint8_t>(newest));
                     auto cleared = coe.upload_value(kDiagHistory, kNewMessages);
                     auto text = [](const Expected<std::uint32_t, SdoError>& v) { return v ? std::to_string(*v) : describe_sdo(v.error()); };
                     return CaseResult::compare("1 then 0", text(set) + " then " + text(cleared));
                   }});
  cases.push_back({"diag.10f3_acknowledge", "ETG.1020 §13 10F3h:03/05: in acknowledge mode (flags bit 4) writing the newest message's subindex to 10F3h:03 acknowledges it: 10F3h:03 reads it back, 10F3h:04 = 0",
                   [](Context& ctx) {
                     if (auto c = need_history(ctx)) return *c;
                     CoeClient coe = ctx.coe();
                     auto flags = coe.upload_value(kDiagHistory, kFlags);
                     if (!flags) return CaseResult::skip("no 10F3h:05 flags: " + describe_sdo(flags.error()));
                     if (auto r = coe.download_value(kDiagHistory, kFlags, *flags | kFlagAcknowledgeMode, 2); !r) {
                       return CaseResult::skip("acknowledge mode not accepted: " + describe_sdo(r.error()));
                     }
                     // Acknowledge what is there, so the new message is not dropped.
                     if (auto old = coe.upload_value(kDiagHistory, kNewest); old && *old != 0) {
                       (void)coe.download_value(kDiagHistory, kNewestAcknowledged, *old, 1);
                     }
                     std::uint32_t newest = 0;
                     auto restore = [&] { (void)coe.download_value(kDiagHistory, kFlags, *flags, 2); };
                     if (auto c = new_message(ctx, newest)) {
                       restore();
                       return *c;
                     }
                     auto w = coe.download_value(kDiagHistory, kNewestAcknowledged, newest, 1);
                     auto ack = coe.upload_value(kDiagHistory, kNewestAcknowledged);
                     auto fresh = coe.upload_value(kDiagHistory, kNewMessages);
                     restore();
                     if (!w) return CaseResult::failed("10F3h:03 writable", describe_sdo(w.error()));
                     const std::string want = "03 = " + std::to_string(newest) + ", 04 = 0";
                     return CaseResult::compare(want, "03 = " + (ack ? std::to_string(*ack) : describe_sdo(ack.error())) +
                                                          ", 04 = " + (fresh ? std::to_string(*fresh) : describe_sdo(fresh.error())));
                   }});
  cases.push_back({"diag.10f3_refuses_acknowledge_of_non_message", "ETG.1020 §13 10F3h:03: subindices 1-5 hold no message; writing one is refused (abort 0609003xh)",
                   [](Context& ctx) {
                     if (auto c = need_history(ctx)) return *c;
                     CoeClient coe = ctx.coe();
                     auto r = coe.download_value(kDiagHistory, kNewestAcknowledged, kMaxMessages, 1);
                     if (r) return CaseResult::failed("abort 0x0609003x", "accepted");
                     const std::string seen = describe_sdo(r.error());
                     if (seen == "abort 0x06010002") return CaseResult::skip("10F3h:03 is read-only on this device (abort 0x06010002)");
                     return seen.rfind("abort 0x0609003", 0) == 0 ? CaseResult::pass("abort 0x0609003x", seen)
                                                                  : CaseResult::failed("abort 0x0609003x", seen);
                   }});
  return cases;
}

}  // namespace ecat::master::conformance
