// Device file (the ESI source, ETG.2000) against what the slave reports over
// the bus: SII (ETG.2010, sii-eeprom.md §4 mapping) and object dictionary.
#include <string>

#include "apps/ecat-conform/target.hpp"
#include "master/coe_client.hpp"

namespace ecat::conform {

namespace {

using master::conformance::Case;
using master::conformance::CaseResult;
using master::conformance::Context;
using master::conformance::hex;

std::string sm_text(std::uint16_t start, std::uint16_t length, std::uint8_t control, std::uint8_t type) {
  return hex(start, 4) + "/" + std::to_string(length) + "/" + hex(control, 2) + "/t" + std::to_string(type);
}

}  // namespace

std::vector<Case> device_file_cases(const od::DeviceDescription& device) {
  const od::DeviceDescription* d = &device;  // the Target owns it for the whole run
  std::vector<Case> cases;
  cases.push_back({"esi.sync_managers_match_sii", "ETG.2000 Sm elements -> SII SYNCM category (sii-eeprom.md §3.4, §4)",
                   [d](Context& ctx) {
                     std::string want, seen;
                     const auto& sms = ctx.info().sii.sync_managers;
                     for (std::size_t i = 0; i < d->sync_managers.size(); ++i) {
                       const auto& sm = d->sync_managers[i];
                       // A process-data SM with size 0 means "from the PDOs": any SII length is fine.
                       const bool any_length = sm.default_size == 0 &&
                                               (sm.type == od::SmType::Outputs || sm.type == od::SmType::Inputs);
                       want += sm_text(sm.start_address, sm.default_size, sm.control, static_cast<std::uint8_t>(sm.type)) + " ";
                       if (i >= sms.size()) {
                         seen += "missing ";
                         continue;
                       }
                       seen += sm_text(sms[i].start, any_length ? sm.default_size : sms[i].length, sms[i].control,
                                       sms[i].type) + " ";
                     }
                     return CaseResult::compare(want, seen);
                   }});
  cases.push_back({"esi.mailbox_matches_sii", "ETG.2000 Mailbox (CoE/FoE/EoE/SoE, CoE details) -> SII word 0x1C and GENERAL byte 5",
                   [d](Context& ctx) {
                     namespace sii = master::sii;
                     const auto& m = d->mailbox;
                     const auto protocols = static_cast<std::uint16_t>((m.coe ? sii::kProtoCoe : 0) | (m.foe ? sii::kProtoFoe : 0) |
                                                                       (m.eoe ? sii::kProtoEoe : 0) | (m.soe ? sii::kProtoSoe : 0));
                     // ETG.2000: SdoInfo, PdoAssign ... are attributes of Mailbox/CoE, so a
                     // device without CoE has no CoE details (ETG.2010 GENERAL byte 5 = 0);
                     // the device file's defaults for them mean nothing there.
                     const auto details = !m.coe ? std::uint8_t{0} : static_cast<std::uint8_t>(
                         sii::kCoeSdo | (m.sdo_info ? sii::kCoeSdoInfo : 0) |
                         (m.pdo_assign ? sii::kCoePdoAssign : 0) | (m.pdo_config ? sii::kCoePdoConfig : 0) |
                         (m.pdo_upload ? sii::kCoeUploadAtStartup : 0) | (m.complete_access ? sii::kCoeCompleteAccess : 0));
                     const auto& s = ctx.info().sii;
                     const std::uint8_t seen_details = s.general ? s.general->coe_details : 0;
                     return CaseResult::compare("protocols " + hex(protocols, 4) + " CoE details " + hex(details, 2),
                                                "protocols " + hex(s.mailbox_protocols, 4) + " CoE details " + hex(seen_details, 2));
                   }});
  cases.push_back({"esi.esc_matches_registers", "Device ESC properties -> ESC registers 0x0004/0x0005/0x0008 (ESC Section II p.13)",
                   [d](Context& ctx) {
                     const auto& e = ctx.info().esc;
                     auto text = [](unsigned fmmus, unsigned sms, bool dc, bool no_lrw) {
                       return std::to_string(fmmus) + " FMMUs, " + std::to_string(sms) + " SMs, DC " + (dc ? "yes" : "no") +
                              ", LRW " + (no_lrw ? "no" : "yes");
                     };
                     return CaseResult::compare(
                         text(d->esc.fmmu_count, d->esc.sm_count, d->esc.dc_supported, d->esc.no_lrw),
                         text(e.fmmus, e.sync_managers, e.has_dc(), (e.features & master::EscInfo::kFeatureNoLrw) != 0));
                   }});
  cases.push_back({"esi.pdo_mappings_match_od", "ETG.2000 RxPdo/TxPdo entries = CoE 0x16xx/0x1Axx mapping (coe-mailbox.md §11.1)",
                   [d](Context& ctx) {
                     if (auto r = ctx.go_to(master::AlState::PreOp); !r) return CaseResult::failed("reach PreOp", r.error());
                     if (!ctx.info().sii.has_coe()) return CaseResult::skip("no CoE");
                     master::CoeClient coe = ctx.coe();
                     std::string mismatches;
                     std::size_t checked = 0;
                     for (const auto* list : {&d->rx_pdos, &d->tx_pdos}) {
                       for (const auto& pdo : *list) {
                         std::vector<std::uint32_t> want;
                         for (const auto& e : pdo.entries) {
                           want.push_back((static_cast<std::uint32_t>(e.index) << 16) |
                                          (static_cast<std::uint32_t>(e.subindex) << 8) | e.bit_length);
                         }
                         auto got = coe.read_pdo_mapping(pdo.index);
                         ++checked;
                         if (!got || *got != want) mismatches += hex(pdo.index, 4) + " ";
                       }
                     }
                     return CaseResult::compare(std::to_string(checked) + " PDOs equal",
                                                mismatches.empty() ? std::to_string(checked) + " PDOs equal"
                                                                   : "differ: " + mismatches);
                   }});
  return cases;
}

}  // namespace ecat::conform
