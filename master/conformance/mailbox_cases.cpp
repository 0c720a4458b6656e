// Mailbox transport behaviour (ETG.1000.4 §5.6, ETG.1000.6 §5.6.1; Section I
// §8.2; coe-mailbox.md §1-§3): error replies, counter repeat detection, the
// SM1 repeat request.
#include <algorithm>

#include "master/conformance/suite.hpp"

namespace ecat::master::conformance {

namespace {

constexpr Nanoseconds kShortTimeout = std::chrono::milliseconds(50);
constexpr std::uint16_t kIdentity = 0x1018;
constexpr std::uint16_t kDeviceType = 0x1000;

std::string error_reply(const Expected<MailboxMessage, MasterError>& m, const Master& master) {
  if (m) return "reply type " + hex(m->header.type, 1);
  if (m.error() == MasterError::MailboxErrorReply) {
    return "mailbox error " + hex(static_cast<std::uint16_t>(master.last_mailbox_error()), 4);
  }
  return std::string(describe(m.error()));
}

// Index echoed in an SDO reply payload (CoE header + command + index).
std::optional<std::uint16_t> sdo_index(const MailboxMessage& m) {
  if (m.header.type != mbx::kTypeCoe || m.payload.size() < 5) return std::nullopt;
  return load_le<std::uint16_t>(m.payload.data() + 3);
}

CaseResult bad_header(Context& ctx, std::uint16_t length, std::vector<std::string> expected) {
  if (auto r = ctx.go_to(AlState::PreOp); !r) return CaseResult::failed("reach PreOp", r.error());
  if (!ctx.info().sii.has_mailbox()) return CaseResult::skip("no mailbox");
  const std::uint8_t counter = mbx::next_counter(ctx.info().mailbox_counter);
  const auto req = CoeClient::upload_request(kIdentity, 1, false);
  if (auto r = ctx.master().mailbox_send_raw(ctx.slave(), mbx::kTypeCoe, counter, req, length); !r) {
    return CaseResult::failed("request sent", std::string(describe(r.error())));
  }
  ctx.info().mailbox_counter = counter;
  const std::string seen = error_reply(ctx.master().mailbox_receive(ctx.slave(), ctx.master().config().mailbox_timeout),
                                       ctx.master());
  std::string want;
  for (const auto& e : expected) want += (want.empty() ? "" : " | ") + e;
  const bool ok = std::find(expected.begin(), expected.end(), seen) != expected.end();
  return ok ? CaseResult::pass(want, seen) : CaseResult::failed(want, seen);
}

}  // namespace

std::vector<Case> mailbox_cases() {
  std::vector<Case> cases;
  cases.push_back({"mailbox.unsupported_protocol",
                   "ETG.1000.6 §5.6 mailbox error reply, code 0x0002 protocol not supported (coe-mailbox.md §2)",
                   [](Context& ctx) {
                     if (auto r = ctx.go_to(AlState::PreOp); !r) return CaseResult::failed("reach PreOp", r.error());
                     if (!ctx.info().sii.has_mailbox()) return CaseResult::skip("no mailbox");
                     const std::uint16_t protocols = ctx.info().sii.mailbox_protocols;
                     const std::pair<std::uint8_t, std::uint16_t> candidates[]{
                         {mbx::kTypeSoe, sii::kProtoSoe}, {mbx::kTypeAoe, sii::kProtoAoe},
                         {mbx::kTypeVoe, sii::kProtoVoe}, {mbx::kTypeEoe, sii::kProtoEoe}};
                     for (auto [type, bit] : candidates) {
                       if ((protocols & bit) != 0) continue;
                       const std::uint8_t payload[8]{};
                       if (auto s = ctx.master().mailbox_send(ctx.slave(), type, payload); !s) {
                         return CaseResult::failed("request sent", std::string(describe(s.error())));
                       }
                       return CaseResult::compare(
                           "mailbox error 0x0002",
                           error_reply(ctx.master().mailbox_receive(ctx.slave(), ctx.master().config().mailbox_timeout),
                                       ctx.master()));
                     }
                     return CaseResult::skip("every mailbox protocol advertised");
                   }});
  cases.push_back({"mailbox.zero_length", "ETG.1000.6 §5.6 mailbox error reply, code 0x0005 invalid header, length 0 (coe-mailbox.md §2)",
                   [](Context& ctx) { return bad_header(ctx, 0, {"mailbox error 0x0005"}); }});
  cases.push_back({"mailbox.length_beyond_sm",
                   "ETG.1000.6 §5.6 mailbox error reply for length > SM0 size - 6: 0x0005 (SOES) or 0x0008 invalid size (coe-mailbox.md §1/§2)",
                   [](Context& ctx) {
                     return bad_header(ctx, static_cast<std::uint16_t>(ctx.info().sii.rx_mailbox_size),
                                       {"mailbox error 0x0005", "mailbox error 0x0008"});
                   }});
  cases.push_back({"mailbox.counter_repeat",
                   "ETG.1000.4 §5.6 mailbox counter: a request with the previous non-zero counter is a repeat and is not executed again (coe-mailbox.md §1)",
                   [](Context& ctx) {
                     if (auto r = ctx.go_to(AlState::PreOp); !r) return CaseResult::failed("reach PreOp", r.error());
                     if (!ctx.info().sii.has_coe()) return CaseResult::skip("no CoE");
                     Master& m = ctx.master();
                     const std::uint8_t c = mbx::next_counter(ctx.info().mailbox_counter);
                     const auto first = CoeClient::upload_request(kIdentity, 1, false);
                     const auto second = CoeClient::upload_request(kDeviceType, 0, false);
                     if (auto r = m.mailbox_send_raw(ctx.slave(), mbx::kTypeCoe, c, first); !r) {
                       return CaseResult::failed("first request", std::string(describe(r.error())));
                     }
                     auto a = m.mailbox_receive(ctx.slave(), m.config().mailbox_timeout);
                     if (!a || sdo_index(*a) != kIdentity) return CaseResult::failed("reply to 0x1018", "none");
                     if (auto r = m.mailbox_send_raw(ctx.slave(), mbx::kTypeCoe, c, second); !r) {
                       return CaseResult::failed("repeat sent", std::string(describe(r.error())));
                     }
                     auto b = m.mailbox_receive(ctx.slave(), kShortTimeout);
                     std::string seen = !b ? "repeat: no reply" :
                                        sdo_index(*b) == kDeviceType ? "repeat: executed" : "repeat: last reply again";
                     const std::uint8_t next = mbx::next_counter(c);
                     ctx.info().mailbox_counter = next;
                     if (auto r = m.mailbox_send_raw(ctx.slave(), mbx::kTypeCoe, next, second); !r) {
                       return CaseResult::failed("next request", std::string(describe(r.error())));
                     }
                     auto d = m.mailbox_receive(ctx.slave(), m.config().mailbox_timeout);
                     seen += d && sdo_index(*d) == kDeviceType ? ", next: executed" : ", next: no reply";
                     const bool ok = seen != "repeat: executed, next: executed" && seen.find("next: executed") != std::string::npos;
                     return ok ? CaseResult::pass("repeat not executed, next: executed", seen)
                               : CaseResult::failed("repeat not executed, next: executed", seen);
                   }});
  cases.push_back({"mailbox.repeat_request",
                   "ESC Section I p.65-66 / ETG.1000.4 §5.6: SM1 repeat request (0x080E bit 1) makes the slave resend its last reply (esc-registers.md §7.2)",
                   [](Context& ctx) {
                     if (auto r = ctx.go_to(AlState::PreOp); !r) return CaseResult::failed("reach PreOp", r.error());
                     if (!ctx.info().sii.has_coe()) return CaseResult::skip("no CoE");
                     Master& m = ctx.master();
                     const auto req = CoeClient::upload_request(kIdentity, 1, false);
                     if (auto r = m.mailbox_send(ctx.slave(), mbx::kTypeCoe, req); !r) {
                       return CaseResult::failed("request", std::string(describe(r.error())));
                     }
                     auto a = m.mailbox_receive(ctx.slave(), m.config().mailbox_timeout);
                     if (!a) return CaseResult::failed("reply", std::string(describe(a.error())));
                     const std::vector<std::uint8_t> first(a->payload.begin(), a->payload.end());
                     if (auto r = m.mailbox_repeat_request(ctx.slave()); !r) {
                       return CaseResult::failed("repeat acknowledged (0x080F bit 1)", std::string(describe(r.error())));
                     }
                     auto b = m.mailbox_receive(ctx.slave(), m.config().mailbox_timeout);
                     if (!b) return CaseResult::failed("same reply again", std::string(describe(b.error())));
                     const std::vector<std::uint8_t> again(b->payload.begin(), b->payload.end());
                     return CaseResult::compare("same reply again", again == first ? "same reply again" : "different reply");
                   }});
  return cases;
}

}  // namespace ecat::master::conformance
