// SDO behaviour and abort codes (ETG.1000.6 §5.6.2, CiA 301 §7.2.4.3.17 abort
// codes; coe-mailbox.md §5-§6).
#include <algorithm>

#include "master/conformance/od_walk.hpp"
#include "master/conformance/suite.hpp"

namespace ecat::master::conformance {

namespace {

constexpr std::uint16_t kIdentity = 0x1018;
constexpr std::uint16_t kProfileArea = 0x2000;
constexpr std::uint16_t kFirstUnusedCandidate = 0x5FFF;

std::string seen_of(const Expected<void, SdoError>& r) { return r ? "success" : describe_sdo(r.error()); }
template <typename T>
std::string seen_of(const Expected<T, SdoError>& r) {
  return r ? "success" : describe_sdo(r.error());
}

std::string abort_text(SdoAbortCode c) { return "abort " + hex(static_cast<std::uint32_t>(c), 8); }

CaseResult one_of(const std::vector<SdoAbortCode>& codes, const std::string& seen) {
  std::string want;
  bool ok = false;
  for (auto c : codes) {
    want += (want.empty() ? "" : " | ") + abort_text(c);
    ok = ok || seen == abort_text(c);
  }
  return ok ? CaseResult::pass(want, seen) : CaseResult::failed(want, seen);
}

// Enters PreOp and checks CoE is there.
std::optional<CaseResult> need_coe(Context& ctx) {
  if (auto r = ctx.go_to(AlState::PreOp); !r) return CaseResult::failed("reach PreOp", r.error());
  if (!ctx.info().sii.has_coe()) return CaseResult::skip("no CoE");
  return std::nullopt;
}

// Enters PreOp, checks CoE and SDO Information (SII GENERAL CoE details bit 1,
// ESI Mailbox/CoE@SdoInfo): the cases that search the dictionary for an entry
// to write need it; a device without it (SdoInfo="false") answers SDO
// Information requests with a mailbox error, as it should.
std::optional<CaseResult> need_sdo_info(Context& ctx) {
  if (auto c = need_coe(ctx)) return c;
  const auto& g = ctx.info().sii.general;
  if (!g || (g->coe_details & sii::kCoeSdoInfo) == 0) {
    return CaseResult::skip("no SDO information (SII CoE details): no dictionary list to find an entry in");
  }
  return std::nullopt;
}

// A writable integer entry of at least `min_bytes`, found through SDO info.
Expected<std::optional<WalkedEntry>, SdoError> writable_integer(Context& ctx, std::size_t min_bytes,
                                                                std::uint8_t value_info = kValueInfoBasic,
                                                                bool need_max = false) {
  return walk_od(ctx, kProfileArea, value_info, [&](const WalkedEntry& w) {
    const auto& e = w.entry;
    const std::size_t n = sdo_size(e.data_type, e.bit_length);
    if (!is_integer_type(e.data_type) || n < min_bytes || (e.subindex == 0 && w.object.object_code != kObjectCodeVar)) {
      return false;
    }
    if ((e.access & kAccessWritePreOp) == 0 || (e.access & kAccessReadPreOp) == 0) return false;
    if (need_max && (e.value_info & coe::kValueInfoMaximum) == 0) return false;
    return true;
  });
}

}  // namespace

std::vector<Case> sdo_cases() {
  std::vector<Case> cases;
  cases.push_back({"sdo.abort_object_not_found", "ETG.1000.6 §5.6.2 / CiA 301 SDO abort 0x06020000 object does not exist (coe-mailbox.md §6)",
                   [](Context& ctx) {
                     if (auto c = need_coe(ctx)) return *c;
                     CoeClient coe = ctx.coe();
                     std::uint16_t index = kFirstUnusedCandidate;
                     if (auto list = coe.od_list()) {
                       while (index > kProfileArea && std::find(list->begin(), list->end(), index) != list->end()) --index;
                     }
                     return CaseResult::compare(abort_text(SdoAbortCode::ObjectNotFound), seen_of(coe.upload(index, 0)));
                   }});
  cases.push_back({"sdo.abort_subindex_not_found", "ETG.1000.6 §5.6.2 / CiA 301 SDO abort 0x06090011 subindex does not exist (coe-mailbox.md §6)",
                   [](Context& ctx) {
                     if (auto c = need_coe(ctx)) return *c;
                     CoeClient coe = ctx.coe();
                     auto n = coe.upload_value(kIdentity, 0);
                     if (!n) return CaseResult::failed("0x1018:00 readable", describe_sdo(n.error()));
                     const auto sub = static_cast<std::uint8_t>(*n + 1);
                     return CaseResult::compare(abort_text(SdoAbortCode::SubindexNotFound), seen_of(coe.upload(kIdentity, sub)));
                   }});
  cases.push_back({"sdo.abort_write_read_only", "ETG.1000.6 §5.6.2 / CiA 301 SDO abort 0x06010002 write to read-only 0x1018:01 (coe-mailbox.md §6)",
                   [](Context& ctx) {
                     if (auto c = need_coe(ctx)) return *c;
                     CoeClient coe = ctx.coe();
                     return CaseResult::compare(abort_text(SdoAbortCode::ReadOnly),
                                                seen_of(coe.download_value(kIdentity, 1, 0x12345678, 4)));
                   }});
  cases.push_back({"sdo.abort_length_too_high", "ETG.1000.6 §5.6.2 / CiA 301 SDO abort 0x06070012 (or 0x06070010): data longer than the entry (coe-mailbox.md §5.2)",
                   [](Context& ctx) {
                     if (auto c = need_sdo_info(ctx)) return *c;
                     auto w = writable_integer(ctx, 1);
                     if (!w) return CaseResult::failed("SDO information", describe_sdo(w.error()));
                     if (!*w) return CaseResult::skip("no writable integer entry found");
                     const auto& e = (*w)->entry;
                     std::vector<std::uint8_t> data(sdo_size(e.data_type, e.bit_length) + 1, 0);
                     CoeClient coe = ctx.coe();
                     return one_of({SdoAbortCode::LengthTooHigh, SdoAbortCode::LengthMismatch},
                                   seen_of(coe.download(e.index, e.subindex, data)));
                   }});
  cases.push_back({"sdo.abort_length_too_low", "ETG.1000.6 §5.6.2 / CiA 301 SDO abort 0x06070013 (or 0x06070010): data shorter than the entry (coe-mailbox.md §5.2)",
                   [](Context& ctx) {
                     if (auto c = need_sdo_info(ctx)) return *c;
                     auto w = writable_integer(ctx, 2);
                     if (!w) return CaseResult::failed("SDO information", describe_sdo(w.error()));
                     if (!*w) return CaseResult::skip("no writable entry of 2+ bytes found");
                     const auto& e = (*w)->entry;
                     std::vector<std::uint8_t> data(sdo_size(e.data_type, e.bit_length) - 1, 0);
                     CoeClient coe = ctx.coe();
                     return one_of({SdoAbortCode::LengthTooLow, SdoAbortCode::LengthMismatch},
                                   seen_of(coe.download(e.index, e.subindex, data)));
                   }});
  cases.push_back({"sdo.abort_value_range", "ETG.1000.6 §5.6.2 / CiA 301 SDO abort 0x06090031 (or 0x06090030): value above the entry's maximum (coe-mailbox.md §6)",
                   [](Context& ctx) {
                     if (auto c = need_sdo_info(ctx)) return *c;
                     auto w = writable_integer(ctx, 1, kValueInfoBasic | kValueInfoRange, true);
                     if (!w) return CaseResult::failed("SDO information", describe_sdo(w.error()));
                     if (!*w) return CaseResult::skip("no writable entry with a maximum value found");
                     const auto& e = (*w)->entry;
                     const std::size_t n = sdo_size(e.data_type, e.bit_length);
                     const std::size_t max_at = e.value_data.size() - n;  // maximum is the last element
                     std::uint64_t max = 0;
                     for (std::size_t i = 0; i < n; ++i) max |= static_cast<std::uint64_t>(e.value_data[max_at + i]) << (8 * i);
                     const std::uint64_t type_max = is_signed_type(e.data_type) ? (1ull << (8 * n - 1)) - 1 : (1ull << (8 * n)) - 1;
                     if (max >= type_max) return CaseResult::skip("maximum is the type's maximum");
                     CoeClient coe = ctx.coe();
                     return one_of({SdoAbortCode::ValueTooHigh, SdoAbortCode::ValueRange},
                                   seen_of(coe.download_value(e.index, e.subindex, static_cast<std::uint32_t>(max + 1), n)));
                   }});
  cases.push_back({"sdo.write_read_back", "ETG.1000.6 §5.6.2 SDO download then upload returns the value written (coe-mailbox.md §5)",
                   [](Context& ctx) {
                     if (auto c = need_sdo_info(ctx)) return *c;
                     auto w = writable_integer(ctx, 1);
                     if (!w) return CaseResult::failed("SDO information", describe_sdo(w.error()));
                     if (!*w) return CaseResult::skip("no writable integer entry found");
                     const auto& e = (*w)->entry;
                     CoeClient coe = ctx.coe();
                     auto old = coe.upload(e.index, e.subindex);
                     if (!old) return CaseResult::failed("upload", describe_sdo(old.error()));
                     if (auto r = coe.download(e.index, e.subindex, *old); !r) {
                       return CaseResult::failed("download of the current value", describe_sdo(r.error()));
                     }
                     auto back = coe.upload(e.index, e.subindex);
                     return CaseResult::compare("same value", back && *back == *old ? "same value" : seen_of(back));
                   }});
  cases.push_back({"sdo.complete_access_identity",
                   "ETG.1000.6 §5.6.2 complete access from subindex 0: SI0 in a 16-bit slot, then the entries (coe-mailbox.md §5.3)",
                   [](Context& ctx) {
                     if (auto c = need_coe(ctx)) return *c;
                     const auto& g = ctx.info().sii.general;
                     if (!g || (g->coe_details & sii::kCoeCompleteAccess) == 0) return CaseResult::skip("no complete access in SII");
                     CoeClient coe = ctx.coe();
                     auto d = coe.upload(kIdentity, 0, true);
                     if (!d) return CaseResult::failed("identity record", describe_sdo(d.error()));
                     const std::size_t n = (*d)[0];
                     std::string seen = "SI0 " + std::to_string(n) + ", " + std::to_string(d->size()) + " bytes";
                     std::string want = "SI0 " + std::to_string(n) + ", " + std::to_string(2 + 4 * n) + " bytes";
                     if (d->size() >= 6 && load_le<std::uint32_t>(d->data() + 2) != ctx.info().sii.vendor_id) {
                       seen += ", vendor differs from SII";
                     }
                     return CaseResult::compare(want, seen);
                   }});
  return cases;
}

}  // namespace ecat::master::conformance
