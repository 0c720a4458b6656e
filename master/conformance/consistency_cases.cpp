// ESI/device file <-> SII <-> object dictionary consistency, SDO information
// against SDO uploads, and PDO remapping (ETG.1000.6 §5.4 SII, §5.6.3 SDO
// information, §5.6.7 PDO mapping/assignment; ETG.2010; sii-eeprom.md §5,
// masters.md §6).
#include <algorithm>
#include <string>

#include "master/conformance/od_walk.hpp"
#include "master/conformance/suite.hpp"

namespace ecat::master::conformance {

namespace {

constexpr std::uint16_t kIdentity = 0x1018;
constexpr std::uint16_t kDeviceType = 0x1000;
constexpr std::uint16_t kSmTypes = 0x1C00;
constexpr std::uint16_t kMinMailboxAddress = 0x1000;

std::string ident(std::uint32_t v, std::uint32_t p, std::uint32_t r) {
  return "vendor " + hex(v, 8) + " product " + hex(p, 8) + " revision " + hex(r, 8);
}

std::optional<CaseResult> need_coe(Context& ctx) {
  if (auto r = ctx.go_to(AlState::PreOp); !r) return CaseResult::failed("reach PreOp", r.error());
  if (!ctx.info().sii.has_coe()) return CaseResult::skip("no CoE");
  return std::nullopt;
}

// First RxPDO the SII does not mark as fixed content.
std::optional<std::uint16_t> configurable_rx_pdo(Context& ctx) {
  for (const auto& p : ctx.info().sii.rx_pdos) {
    if ((p.flags & sii::kPdoFixed) == 0) return p.index;
  }
  return std::nullopt;
}

std::string join(const std::vector<std::uint16_t>& v) {
  std::string s;
  // Appended piece by piece: `(cond ? "" : ",") + std::string` makes GCC 12
  // at -O3 report a -Wrestrict false positive inside std::string.
  for (auto x : v) {
    if (!s.empty()) s += ',';
    s += hex(x, 4);
  }
  return s.empty() ? "none" : s;
}

}  // namespace

std::vector<Case> consistency_cases() {
  std::vector<Case> cases;
  cases.push_back({"sii.checksum", "ETG.1000.6 §5.4 / ESC Section I p.93: CRC-8 of SII words 0-6 in word 7 (sii-eeprom.md §2)",
                   [](Context& ctx) {
                     const auto& s = ctx.info().sii;
                     const std::uint8_t crc = sii::config_crc(ConstBytes(ctx.info().sii_image.data(), sii::kChecksumCoveredBytes));
                     return CaseResult::compare(hex(crc, 2), hex(s.checksum, 2));
                   }});
  cases.push_back({"sii.mailbox_words_match_syncm", "ETG.2010 / sii-eeprom.md §5 #3: words 0x18-0x1B equal SYNCM SM0/SM1",
                   [](Context& ctx) {
                     const auto& s = ctx.info().sii;
                     if (!s.has_mailbox()) return CaseResult::skip("no mailbox");
                     if (s.sync_managers.size() < 2) return CaseResult::failed("SYNCM with SM0/SM1", "missing");
                     auto fmt = [](std::uint16_t a, std::uint16_t b, std::uint16_t c, std::uint16_t d) {
                       return hex(a, 4) + "/" + std::to_string(b) + " " + hex(c, 4) + "/" + std::to_string(d);
                     };
                     return CaseResult::compare(
                         fmt(s.rx_mailbox_offset, s.rx_mailbox_size, s.tx_mailbox_offset, s.tx_mailbox_size),
                         fmt(s.sync_managers[0].start, s.sync_managers[0].length, s.sync_managers[1].start,
                             s.sync_managers[1].length));
                   }});
  cases.push_back({"sii.category_layout",
                   "ETG.2010: GENERAL 16 words, SYNCM before TXPDO/RXPDO (IgH), mailbox SMs at >= 0x1000 (masters.md §2.2, §6 #19/#29)",
                   [](Context& ctx) {
                     const auto& s = ctx.info().sii;
                     std::string problems;
                     if (!s.general) problems += "no GENERAL; ";
                     const auto& order = s.category_order;
                     auto first = [&](std::uint16_t t) {
                       return std::find(order.begin(), order.end(), t) - order.begin();
                     };
                     const auto syncm = first(static_cast<std::uint16_t>(sii::Category::SyncM));
                     if (first(static_cast<std::uint16_t>(sii::Category::TxPdo)) < syncm ||
                         first(static_cast<std::uint16_t>(sii::Category::RxPdo)) < syncm) {
                       problems += "PDO category before SYNCM; ";
                     }
                     if (s.has_mailbox() && (s.rx_mailbox_offset < kMinMailboxAddress || s.tx_mailbox_offset < kMinMailboxAddress)) {
                       problems += "mailbox below 0x1000; ";
                     }
                     for (const auto& sm : s.sync_managers) {
                       if ((sm.enable & ~0x0Fu) != 0) problems += "SM enable byte has undefined bits; ";
                     }
                     return CaseResult::compare("consistent", problems.empty() ? "consistent" : problems);
                   }});
  cases.push_back({"sii.identity_matches_device_file", "ETG.2000 Device/Type and Vendor/Id vs SII words 0x08-0x0D (sii-eeprom.md §4)",
                   [](Context& ctx) {
                     if (!ctx.options().identity) return CaseResult::skip("no device file given");
                     const auto& id = *ctx.options().identity;
                     const auto& s = ctx.info().sii;
                     return CaseResult::compare(ident(id.vendor_id, id.product_code, id.revision),
                                                ident(s.vendor_id, s.product_code, s.revision));
                   }});
  cases.push_back({"od.identity_matches_sii", "ETG.1000.6 §5.4: SII words 0x08-0x0F equal CoE 0x1018:01-04 (sii-eeprom.md §1, §5 #2)",
                   [](Context& ctx) {
                     if (auto c = need_coe(ctx)) return *c;
                     CoeClient coe = ctx.coe();
                     const auto& s = ctx.info().sii;
                     // CiA 301 §7.5.2.31: 1018h:01 is mandatory, :02-:04 optional; a device
                     // with 1018h:00 = 3 (Inovance IS620N) has no serial number entry, so
                     // the entries it has are compared with the SII.
                     constexpr std::uint64_t kIdentityEntries = 4;
                     auto count = coe.upload_value(kIdentity, 0);
                     const std::uint64_t n = count ? std::clamp<std::uint64_t>(*count, 1, kIdentityEntries) : kIdentityEntries;
                     const std::uint32_t sii_values[] = {s.vendor_id, s.product_code, s.revision, s.serial};
                     std::string seen, expected;
                     for (std::uint8_t sub = 1; sub <= n; ++sub) {
                       auto v = coe.upload_value(kIdentity, sub);
                       if (sub > 1) seen += ' ', expected += ' ';
                       seen += v ? hex(*v, 8) : describe_sdo(v.error());
                       expected += hex(sii_values[sub - 1], 8);
                     }
                     return CaseResult::compare(expected, seen);
                   }});
  cases.push_back({"od.mandatory_objects", "CiA 301 (0x1000, 0x1018) and ETG.1000.6 (0x1C00, needed by SOEM: masters.md §6 #24) in the OD list",
                   [](Context& ctx) {
                     if (auto c = need_coe(ctx)) return *c;
                     const auto& g = ctx.info().sii.general;
                     if (!g || (g->coe_details & sii::kCoeSdoInfo) == 0) return CaseResult::skip("no SDO information");
                     CoeClient coe = ctx.coe();
                     auto list = coe.od_list();
                     if (!list) return CaseResult::failed("OD list", describe_sdo(list.error()));
                     std::vector<std::uint16_t> missing;
                     for (std::uint16_t i : {kDeviceType, kIdentity, kSmTypes}) {
                       if (std::find(list->begin(), list->end(), i) == list->end()) missing.push_back(i);
                     }
                     return CaseResult::compare("none missing", missing.empty() ? "none missing" : "missing " + join(missing));
                   }});
  cases.push_back({"od.sm_types_match_sii", "ETG.1000.6 0x1C00:n equals the SII SYNCM type of SM n-1 (coe-mailbox.md §11.2, sii-eeprom.md §3.4)",
                   [](Context& ctx) {
                     if (auto c = need_coe(ctx)) return *c;
                     CoeClient coe = ctx.coe();
                     auto n = coe.upload_value(kSmTypes, 0);
                     if (!n) return CaseResult::failed("0x1C00 readable", describe_sdo(n.error()));
                     std::string want, seen;
                     const auto& sms = ctx.info().sii.sync_managers;
                     for (std::uint8_t i = 1; i <= *n && i <= sms.size(); ++i) {
                       auto t = coe.upload_value(kSmTypes, i);
                       want += std::to_string(sms[i - 1u].type);
                       seen += t ? std::to_string(*t) : "?";
                     }
                     return CaseResult::compare(want, seen);
                   }});
  cases.push_back({"od.default_pdos_match_sii", "ETG.2010 TXPDO/RXPDO categories: default SM assignment equals 0x1C12/0x1C13 (sii-eeprom.md §3.6)",
                   [](Context& ctx) {
                     if (auto c = need_coe(ctx)) return *c;
                     if (ctx.info().sii.tx_pdos.empty() && ctx.info().sii.rx_pdos.empty()) {
                       return CaseResult::skip("SII has no PDO categories (masters read 0x1C12/0x1C13)");
                     }
                     CoeClient coe = ctx.coe();
                     std::string want, seen;
                     for (auto [assign, tx, sm] : {std::tuple{coe::kRxPdoAssign, false, std::uint8_t{2}},
                                                   std::tuple{coe::kTxPdoAssign, true, std::uint8_t{3}}}) {
                       std::vector<std::uint16_t> sii_pdos;
                       for (const auto& p : tx ? ctx.info().sii.tx_pdos : ctx.info().sii.rx_pdos) {
                         if (p.sync_manager == sm) sii_pdos.push_back(p.index);
                       }
                       auto od = coe.read_pdo_assignment(assign);
                       // No process-data SM on this side in the SII: the
                       // assignment object need not exist (abort 06020000),
                       // which is "none", as masters read it.
                       const auto& sms = ctx.info().sii.sync_managers;
                       const bool sm_in_sii =
                           sm < sms.size() && sms[sm].type == (tx ? sii::kSmTypeInputs : sii::kSmTypeOutputs);
                       const bool absent = !od && od.error().from_slave && od.error().code == SdoAbortCode::ObjectNotFound;
                       want += hex(assign, 4) + ": " + join(sii_pdos) + "; ";
                       seen += hex(assign, 4) + ": " +
                               (od ? join(*od) : absent && !sm_in_sii ? join({}) : describe_sdo(od.error())) + "; ";
                     }
                     return CaseResult::compare(want, seen);
                   }});
  cases.push_back({"od.sdo_info_matches_upload",
                   "ETG.1000.6 §5.6.3 SDO information: entry description bit length equals the size of the SDO upload (coe-mailbox.md §7.3)",
                   [](Context& ctx) {
                     if (auto c = need_coe(ctx)) return *c;
                     const auto& g = ctx.info().sii.general;
                     if (!g || (g->coe_details & sii::kCoeSdoInfo) == 0) return CaseResult::skip("no SDO information");
                     CoeClient coe = ctx.coe();
                     std::size_t checked = 0;
                     std::string mismatches;
                     auto walked = walk_od(ctx, 0, kValueInfoBasic, [&](const WalkedEntry& w) {
                       const auto& e = w.entry;
                       if ((e.access & kAccessReadPreOp) == 0 || e.bit_length == 0) return false;
                       const std::size_t want = sdo_size(e.data_type, e.bit_length);
                       auto up = coe.upload(e.index, e.subindex);
                       ++checked;
                       const bool ok = up && (want == 0 ? up->size() <= (e.bit_length + 7u) / 8u : up->size() == want);
                       if (!ok && mismatches.size() < 200) {
                         mismatches += hex(e.index, 4) + ":" + std::to_string(e.subindex) + " " +
                                       (up ? std::to_string(up->size()) + " bytes vs " + std::to_string(e.bit_length) + " bits"
                                           : describe_sdo(up.error())) + "; ";
                       }
                       return false;
                     });
                     if (!walked) return CaseResult::failed("OD walk", describe_sdo(walked.error()));
                     return CaseResult::compare("all consistent",
                                                mismatches.empty() ? "all consistent" : mismatches);
                   }});
  cases.push_back({"pdo.remap_roundtrip",
                   "ETG.1000.6 PDO mapping/assignment (coe-mailbox.md §11.1/§11.2): a configurable mapping and 0x1C12 rewritten SI0=0, entries, SI0=n read back unchanged; SafeOp accepted",
                   [](Context& ctx) {
                     if (auto c = need_coe(ctx)) return *c;
                     const auto& g = ctx.info().sii.general;
                     if (!g || (g->coe_details & (sii::kCoePdoAssign | sii::kCoePdoConfig)) == 0) {
                       return CaseResult::skip("SII advertises neither PDO assign nor PDO config");
                     }
                     CoeClient coe = ctx.coe();
                     auto assign = coe.read_pdo_assignment(coe::kRxPdoAssign);
                     if (!assign) return CaseResult::failed("0x1C12 readable", describe_sdo(assign.error()));
                     auto pdo = configurable_rx_pdo(ctx);
                     if ((g->coe_details & sii::kCoePdoConfig) != 0 && pdo) {
                       auto mapping = coe.read_pdo_mapping(*pdo);
                       if (!mapping) return CaseResult::failed("mapping readable", describe_sdo(mapping.error()));
                       if (auto r = coe.write_pdo_mapping(*pdo, *mapping); !r) {
                         return CaseResult::failed("mapping of " + hex(*pdo, 4) + " written", describe_sdo(r.error()));
                       }
                       auto back = coe.read_pdo_mapping(*pdo);
                       if (!back || *back != *mapping) return CaseResult::failed("mapping read back unchanged", "differs");
                     }
                     if ((g->coe_details & sii::kCoePdoAssign) != 0) {
                       if (auto r = coe.write_pdo_assignment(coe::kRxPdoAssign, *assign); !r) {
                         return CaseResult::failed("assignment written", describe_sdo(r.error()));
                       }
                       auto back = coe.read_pdo_assignment(coe::kRxPdoAssign);
                       if (!back || *back != *assign) return CaseResult::failed("assignment read back unchanged", "differs");
                     }
                     if (auto r = ctx.go_to(AlState::SafeOp); !r) return CaseResult::failed("SafeOp", r.error());
                     return CaseResult::pass("read back unchanged, SafeOp", "read back unchanged, SafeOp");
                   }});
  cases.push_back({"pdo.remap_assign_configurable",
                   "ETG.1000.6 PDO mapping (coe-mailbox.md §11.1) and §6.4.1 PreOp->SafeOp SM2 size check: a shorter configurable RxPDO changes the expected SM2 length",
                   [](Context& ctx) {
                     if (auto c = need_coe(ctx)) return *c;
                     const auto& g = ctx.info().sii.general;
                     if (!g || (g->coe_details & sii::kCoePdoAssign) == 0 || (g->coe_details & sii::kCoePdoConfig) == 0) {
                       return CaseResult::skip("SII does not advertise PDO assign and config");
                     }
                     auto pdo = configurable_rx_pdo(ctx);
                     if (!pdo) return CaseResult::skip("no configurable RxPDO in the SII");
                     CoeClient coe = ctx.coe();
                     auto assign = coe.read_pdo_assignment(coe::kRxPdoAssign);
                     auto mapping = coe.read_pdo_mapping(*pdo);
                     if (!assign || !mapping) return CaseResult::failed("0x1C12 and mapping readable", "read failed");
                     if (mapping->empty()) return CaseResult::skip("configurable PDO has an empty mapping");
                     std::vector<std::uint32_t> shorter(*mapping);
                     if (shorter.size() > 1) shorter.pop_back();
                     std::uint32_t bits = 0;
                     for (auto e : shorter) bits += e & 0xFFu;
                     const std::string want = "SafeOp with " + std::to_string((bits + 7) / 8) + " output bytes";
                     std::string seen;
                     const std::uint16_t assigned[]{*pdo};
                     if (auto r = coe.write_pdo_mapping(*pdo, shorter); !r) {
                       seen = "mapping write: " + describe_sdo(r.error());
                     } else if (auto a = coe.write_pdo_assignment(coe::kRxPdoAssign, assigned); !a) {
                       seen = "assignment write: " + describe_sdo(a.error());
                     } else if (auto s = ctx.go_to(AlState::SafeOp); !s) {
                       seen = s.error();
                     } else {
                       seen = "SafeOp with " + std::to_string(ctx.info().pd.output_bytes) + " output bytes";
                     }
                     // Put the original mapping and assignment back (PreOp).
                     (void)ctx.go_to(AlState::PreOp);
                     CoeClient restore = ctx.coe();
                     (void)restore.write_pdo_mapping(*pdo, *mapping);
                     (void)restore.write_pdo_assignment(coe::kRxPdoAssign, *assign);
                     return CaseResult::compare(want, seen);
                   }});
  cases.push_back({"pdo.remap_refused_in_safeop",
                   "ETG.1000.6 / CiA 301 PDO assignment is changed in PreOp only: SDO abort in SafeOp (coe-mailbox.md §11.1)",
                   [](Context& ctx) {
                     if (auto r = ctx.go_to(AlState::SafeOp); !r) return CaseResult::failed("reach SafeOp", r.error());
                     if (!ctx.info().sii.has_coe()) return CaseResult::skip("no CoE");
                     CoeClient coe = ctx.coe();
                     const auto before = coe.upload_value(coe::kRxPdoAssign, 0);
                     auto r = coe.download_value(coe::kRxPdoAssign, 0, 0, 1);
                     if (r) {
                       // A slave that wrongly took the write would run every later case
                       // without outputs (KickCAT did: its CiA 402 cases then skipped with
                       // "607Ah is not in the process data"): put the count back.
                       const bool restored = before && coe.download_value(coe::kRxPdoAssign, 0, *before, 1);
                       return CaseResult::failed("SDO abort", restored ? "accepted (1C12h:00 restored to " +
                                                                             std::to_string(*before) + ")"
                                                                       : "accepted (1C12h:00 not restored)");
                     }
                     return r.error().from_slave ? CaseResult::pass("SDO abort", describe_sdo(r.error()))
                                                 : CaseResult::failed("SDO abort", describe_sdo(r.error()));
                   }});
  return cases;
}

}  // namespace ecat::master::conformance
