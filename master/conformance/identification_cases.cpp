// Station alias and explicit device identification (ETG.1000.6 §6.4.1 AL
// control bit 5; ESC Section II 0x0012, 0x0100 bit 24, 0x0120/0x0130 bit 5,
// 0x0134; shared/spec/esm-al-codes.md §5.4, esc-registers.md §2, §4.3).
#include <fmt/format.h>

#include "common/frame.hpp"
#include "master/conformance/suite.hpp"
#include "master/registers.hpp"

namespace ecat::master::conformance {

namespace {

constexpr std::uint8_t kFlagIdentAlStatus = 0x08;      // SII GENERAL flags bit 3 (sii-eeprom.md §3.2)
constexpr std::uint32_t kDlControlAliasEnable = 1u << 24;  // 0x0100 bit 24

// The device offers explicit device identification through AL status
// (SII GENERAL flags bit 3, ESI Info/IdentificationReg134).
std::optional<CaseResult> need_ident(Context& ctx) {
  const auto& g = ctx.info().sii.general;
  if (!g || (g->flags & kFlagIdentAlStatus) == 0) {
    return CaseResult::skip("SII GENERAL flags bit 3 (IdentALSts) clear: the device offers no explicit device identification");
  }
  return std::nullopt;
}

std::string shown_id(const AlStatus& s) {
  return fmt::format("{} ID {} 0x0134 {}", format_status(s), (s.raw & kAlIdentBit) != 0 ? "set" : "clear", hex(s.code, 4));
}

// What an ID request should show: `state` + ID flag, 0x0134 = the ID value.
// The value is the device's (an ID selector or the alias, SOES/SSC); the
// suite knows it only as "not 0" unless it is the alias.
CaseResult request_with_id(Context& ctx, AlState from, AlState to) {
  if (auto c = need_ident(ctx)) return *c;
  if (auto r = ctx.go_to(from); !r) return CaseResult::failed(std::string("reach ") + std::string(describe(from)), r.error());
  auto alias = ctx.master().fprd_u16(ctx.info().station_address, reg::kConfiguredStationAlias);
  if (!alias) return CaseResult::failed("0x0012 readable", std::string(describe(alias.error())));
  if (from == AlState::Init && to == AlState::PreOp && ctx.info().sii.has_mailbox()) {
    if (auto r = ctx.master().configure_mailbox(ctx.slave()); !r) return CaseResult::failed("mailbox SMs", std::string(describe(r.error())));
  }
  auto st = ctx.master().write_al_control(ctx.slave(), static_cast<std::uint16_t>(static_cast<std::uint8_t>(to) | kAlIdentBit));
  if (!st) return CaseResult::failed("AL status", std::string(describe(st.error())));
  AlStatus want;
  want.raw = static_cast<std::uint16_t>(static_cast<std::uint8_t>(to) | kAlIdentBit);
  const std::string expected = format_status(want) + " ID set 0x0134 " + (*alias != 0 ? hex(*alias, 4) + " (alias) or another non-zero ID" : "non-zero ID");
  const bool ok = !st->error() && st->is(to) && (st->raw & kAlIdentBit) != 0 && st->code != 0;
  return ok ? CaseResult::pass(expected, shown_id(*st)) : CaseResult::failed(expected, shown_id(*st));
}

}  // namespace

std::vector<Case> identification_cases() {
  std::vector<Case> cases;
  cases.push_back({"id.request_in_init", "ETG.1000.6 §6.4.1 / ESC Section II 0x0120 bit 5: Init with ID request -> 0x0130 bit 5, 0x0134 = ID value (esm-al-codes.md §5.4)",
                   [](Context& ctx) { return request_with_id(ctx, AlState::Init, AlState::Init); }});
  cases.push_back({"id.request_init_to_preop", "ETG.1000.6 §6.4.1 / ESC Section II 0x0120 bit 5: Init->PreOp with ID request -> PreOp, 0x0130 bit 5, 0x0134 = ID value (esm-al-codes.md §5.4)",
                   [](Context& ctx) { return request_with_id(ctx, AlState::Init, AlState::PreOp); }});
  cases.push_back({"id.cleared_without_request", "ETG.1000.6 §6.4.1 / ESC Section II 0x0130 bit 5: the next request without bit 5 clears the ID flag and 0x0134 (esm-al-codes.md §5.3-§5.4)",
                   [](Context& ctx) {
                     if (auto c = need_ident(ctx)) return *c;
                     if (auto r = ctx.go_to(AlState::PreOp); !r) return CaseResult::failed("reach PreOp", r.error());
                     auto id = ctx.master().write_al_control(ctx.slave(), static_cast<std::uint16_t>(0x02 | kAlIdentBit));
                     if (!id || (id->raw & kAlIdentBit) == 0) {
                       return CaseResult::failed("ID shown first", id ? shown_id(*id) : std::string(describe(id.error())));
                     }
                     auto st = ctx.master().request_state(ctx.slave(), AlState::PreOp);
                     if (!st) return CaseResult::failed("AL status", std::string(describe(st.error())));
                     AlStatus want;
                     want.raw = 0x02;
                     return CaseResult::compare(shown_id(want), shown_id(*st));
                   }});
  cases.push_back({"id.alias_addressing", "ESC Section I p.26 / Section II 0x0100 bit 24: with alias addressing on, FPRD at the alias 0x0012 reaches the slave (WKC 1, same AL status) (esc-registers.md §2, §4.3)",
                   [](Context& ctx) {
                     const std::uint16_t station = ctx.info().station_address;
                     auto alias = ctx.master().fprd_u16(station, reg::kConfiguredStationAlias);
                     if (!alias) return CaseResult::failed("0x0012 readable", std::string(describe(alias.error())));
                     if (*alias == 0) return CaseResult::skip("station alias 0 (SII word 4): the device has no alias to address");
                     if (*alias == station) return CaseResult::skip("the alias equals the station address the master gave");
                     auto dl = ctx.master().fprd_u32(station, reg::kDlControl);
                     if (!dl) return CaseResult::failed("0x0100 readable", std::string(describe(dl.error())));
                     auto now = ctx.master().read_al_status(ctx.slave());
                     if (!now) return CaseResult::failed("AL status readable", std::string(describe(now.error())));
                     const std::string want = "WKC 1 at alias " + hex(*alias, 4) + ", AL status " + format_status(*now);
                     std::string seen;
                     if (auto w = ctx.master().fpwr_u32(station, reg::kDlControl, *dl | kDlControlAliasEnable); !w) {
                       seen = "0x0100 bit 24 write: " + std::string(describe(w.error()));
                     } else {
                       std::uint8_t st[2]{};
                       auto wkc = ctx.master().transact(Command::Fprd, device_address(*alias, reg::kAlStatus), st);
                       AlStatus s;
                       s.raw = load_le<std::uint16_t>(st);
                       seen = wkc ? "WKC " + std::to_string(*wkc) + " at alias " + hex(*alias, 4) + ", AL status " + format_status(s)
                                  : std::string(describe(wkc.error()));
                       (void)ctx.master().fpwr_u32(station, reg::kDlControl, *dl);
                     }
                     return CaseResult::compare(want, seen);
                   }});
  return cases;
}

}  // namespace ecat::master::conformance
