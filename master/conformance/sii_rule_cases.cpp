// SII/ESI rules beyond the schema (ETG.2010 SII categories, ETG.2000 ESI
// rules as a configurator applies them; ETG.1000.6 §5.4): what a master or
// configurator relies on when it reads the EEPROM, checked on the image the
// slave gives over the bus (shared/spec/sii-eeprom.md §1-§5).
#include <fmt/format.h>

#include <algorithm>

#include "common/frame.hpp"
#include "master/conformance/suite.hpp"
#include "master/registers.hpp"

namespace ecat::master::conformance {

namespace {

constexpr std::size_t kSizeUnitBytes = 128;           // word 0x3E: EEPROM size in Kbit - 1 (sii-eeprom.md §1)
constexpr std::uint16_t kSiiVersion = 1;              // word 0x3F
constexpr std::uint8_t kCoeDetailsReserved = 0xC0;    // GENERAL byte 5 bits 7:6
constexpr std::uint8_t kGeneralFlagsReserved = 0xE0;  // GENERAL byte 0x0B bits 7:5
constexpr std::uint8_t kDetailsEnable = 0x01;         // GENERAL CoE/FoE/EoE details bit 0
constexpr std::uint8_t kSmTypeMax = 4;
constexpr std::uint8_t kSmModeMask = 0x03;            // SM control bits 1:0
constexpr std::uint8_t kSmModeBuffered = 0x00;        // 3-buffer: three areas of the length
constexpr unsigned kBuffers = 3;
constexpr std::uint16_t kRxPdoFirst = 0x1600, kRxPdoLast = 0x17FF;
constexpr std::uint16_t kTxPdoFirst = 0x1A00, kTxPdoLast = 0x1BFF;
constexpr std::uint8_t kFmmuUnused = 0x00, kFmmuOutputs = 0x01, kFmmuInputs = 0x02, kFmmuSmStatus = 0x03,
                       kFmmuUnusedPad = 0xFF;
constexpr std::uint8_t kNoSm = 0xFF;
// An expedited SDO request: mailbox header 6 + CoE header 2 + SDO 8 bytes
// (ETG.1000.6 §5.6.2, coe-mailbox.md §1/§5).
constexpr std::uint16_t kMinCoeMailbox = 16;
// Mailbox header alone (ETG.1000.4 §5.6).
constexpr std::uint16_t kMailboxHeaderBytes = 6;
// AssignActivate (DC category, 0x0980 low byte / 0x0981 high byte as one word,
// sii-eeprom.md §3.7): 0x0980 defines bits 0, 4, 5 (esc-registers.md §10).
constexpr std::uint16_t kAssignActivateDefined = 0xFF31;
constexpr std::uint16_t kAssignActivateUnit = 0x0100;   // 0x0981 bit 0
constexpr std::uint16_t kAssignActivateSync0 = 0x0200;  // 0x0981 bit 1
constexpr std::uint32_t kRamStart = 0x1000;
constexpr std::uint16_t kWord0DeviceEmulation = 0x0100;  // SII word 0 bit 8 -> 0x0141 bit 0 (esc-registers.md §4.9)
constexpr std::uint32_t kDigitalOutputs = 0x0F00, kDigitalOutputsEnd = 0x0F04;  // process RAM (ESC Section II p.13, esc-registers.md §3)
constexpr std::uint16_t kChecksumDisabled = 0x88A4;  // debug value, sii-eeprom.md §1 word 7

std::uint16_t word_at(const std::vector<std::uint8_t>& img, std::size_t w) {
  return 2 * w + 1 < img.size() ? load_le<std::uint16_t>(img.data() + 2 * w) : 0xFFFF;
}

struct RawCategory {
  std::uint16_t type = 0;
  std::size_t word = 0;    // header word address
  std::uint16_t words = 0;  // data length
};

// Category headers from word 0x40 to END (or the image end).
std::vector<RawCategory> categories(const std::vector<std::uint8_t>& img, std::optional<std::size_t>& end_word) {
  std::vector<RawCategory> out;
  std::size_t w = sii::kFirstCategory;
  while (2 * (w + 1) <= img.size()) {
    const std::uint16_t type = word_at(img, w);
    if (type == static_cast<std::uint16_t>(sii::Category::End)) {
      end_word = w;
      break;
    }
    const std::uint16_t len = word_at(img, w + 1);
    out.push_back({type, w, len});
    w += 2u + len;
  }
  return out;
}

std::string problems_or(const std::string& problems, const std::string& ok) { return problems.empty() ? ok : problems; }

// Byte range an SM occupies: 3 areas in 3-buffer mode (ESC Section I p.62).
std::uint32_t sm_footprint(const SiiSyncManager& sm) {
  return (sm.control & kSmModeMask) == kSmModeBuffered ? std::uint32_t{sm.length} * kBuffers : sm.length;
}

CaseResult string_indices(Context& ctx) {
  const auto& s = ctx.info().sii;
  const std::size_t n = s.strings.size();
  std::string problems;
  auto check = [&](const std::string& what, std::uint8_t idx) {
    if (idx > n) problems += fmt::format("{} index {}; ", what, idx);
  };
  if (s.general) {
    check("GENERAL group", s.general->group_index);
    check("GENERAL image", s.general->image_index);
    check("GENERAL order", s.general->order_index);
    check("GENERAL name", s.general->name_index);
  }
  for (const auto* pdos : {&s.tx_pdos, &s.rx_pdos}) {
    for (const auto& p : *pdos) {
      check(hex(p.index, 4) + " name", p.name_index);
      for (const auto& e : p.entries) check(hex(p.index, 4) + " entry " + hex(e.index, 4) + " name", e.name_index);
    }
  }
  for (std::size_t i = 0; i < s.dc_modes.size(); ++i) check(fmt::format("DC mode {} name", i), s.dc_modes[i].name_index);
  return CaseResult::compare(fmt::format("all <= {} strings", n), problems_or(problems, fmt::format("all <= {} strings", n)));
}

CaseResult syncm_types(Context& ctx) {
  const auto& s = ctx.info().sii;
  std::string problems;
  for (std::size_t i = 0; i < s.sync_managers.size(); ++i) {
    if (s.sync_managers[i].type > kSmTypeMax) problems += fmt::format("SM{} type {}; ", i, s.sync_managers[i].type);
  }
  if (s.has_mailbox()) {
    if (s.sync_managers.size() < 2) {
      problems += "mailbox without SM0/SM1; ";
    } else {
      if (s.sync_managers[0].type != sii::kSmTypeMailboxOut) problems += fmt::format("SM0 type {} (not 1); ", s.sync_managers[0].type);
      if (s.sync_managers[1].type != sii::kSmTypeMailboxIn) problems += fmt::format("SM1 type {} (not 2); ", s.sync_managers[1].type);
    }
  }
  return CaseResult::compare("valid", problems_or(problems, "valid"));
}

CaseResult pdo_sync_managers(Context& ctx) {
  const auto& s = ctx.info().sii;
  std::string problems;
  for (bool tx : {false, true}) {
    for (const auto& p : tx ? s.tx_pdos : s.rx_pdos) {
      const bool in_range = tx ? (p.index >= kTxPdoFirst && p.index <= kTxPdoLast) : (p.index >= kRxPdoFirst && p.index <= kRxPdoLast);
      if (!in_range) problems += fmt::format("{} {} outside {}; ", tx ? "TxPDO" : "RxPDO", hex(p.index, 4), tx ? "0x1A00-0x1BFF" : "0x1600-0x17FF");
      if (p.sync_manager == kNoSm) continue;
      const std::uint8_t want = tx ? sii::kSmTypeInputs : sii::kSmTypeOutputs;
      if (p.sync_manager >= s.sync_managers.size()) {
        problems += fmt::format("{} on SM{} (not in SYNCM); ", hex(p.index, 4), p.sync_manager);
      } else if (s.sync_managers[p.sync_manager].type != want) {
        problems += fmt::format("{} on SM{} of type {} (want {}); ", hex(p.index, 4), p.sync_manager,
                                s.sync_managers[p.sync_manager].type, want);
      }
    }
  }
  return CaseResult::compare("consistent", problems_or(problems, "consistent"));
}

CaseResult sm_sizes_fit_pdos(Context& ctx) {
  const auto& s = ctx.info().sii;
  // With PDO assignment or configuration the configurator sizes the SMs from
  // the PDOs it writes (vendors give the SYNCM length as the maximum); only
  // fixed process data must fit the SII lengths as they are.
  if (s.has_coe() && s.general && (s.general->coe_details & (sii::kCoePdoAssign | sii::kCoePdoConfig)) != 0) {
    return CaseResult::skip("PDO assignment/configuration (SII CoE details): the SM lengths follow the configured PDOs");
  }
  std::string want, seen;
  for (std::size_t i = 0; i < s.sync_managers.size(); ++i) {
    const auto& sm = s.sync_managers[i];
    if (sm.type != sii::kSmTypeOutputs && sm.type != sii::kSmTypeInputs) continue;
    if (sm.length == 0) continue;  // "size from the PDOs" (ETG.2000 Sm without DefaultSize)
    const std::uint32_t bits = s.default_pdo_bits(sm.type == sii::kSmTypeInputs, static_cast<std::uint8_t>(i));
    if (bits == 0) continue;  // no default PDO on it: sized by the configuration
    want += fmt::format("SM{} {} bytes; ", i, (bits + 7) / 8);
    seen += fmt::format("SM{} {} bytes; ", i, sm.length);
  }
  if (want.empty()) return CaseResult::skip("no process-data SM with both a SYNCM length and default PDOs");
  return CaseResult::compare(want, seen);
}

CaseResult fmmu_usage(Context& ctx) {
  const auto& s = ctx.info().sii;
  if (s.fmmu_usage.empty()) return CaseResult::skip("no FMMU category");
  std::string problems;
  unsigned used = 0;
  bool outputs = false, inputs = false;
  for (std::size_t i = 0; i < s.fmmu_usage.size(); ++i) {
    const std::uint8_t u = s.fmmu_usage[i];
    if (u == kFmmuUnused || u == kFmmuUnusedPad) continue;
    if (u > kFmmuSmStatus) problems += fmt::format("FMMU{} usage {}; ", i, hex(u, 2));
    ++used;
    outputs |= u == kFmmuOutputs;
    inputs |= u == kFmmuInputs;
  }
  std::uint32_t out_bits = 0, in_bits = 0;
  for (const auto& p : s.rx_pdos) out_bits += p.sync_manager == kNoSm ? 0 : p.bit_length();
  for (const auto& p : s.tx_pdos) in_bits += p.sync_manager == kNoSm ? 0 : p.bit_length();
  if (out_bits > 0 && !outputs) problems += "RxPDOs but no outputs FMMU; ";
  if (in_bits > 0 && !inputs) problems += "TxPDOs but no inputs FMMU; ";
  if (used > ctx.info().esc.fmmus) problems += fmt::format("{} FMMUs used, ESC has {} (0x0004); ", used, ctx.info().esc.fmmus);
  return CaseResult::compare("consistent", problems_or(problems, "consistent"));
}

CaseResult sm_areas(Context& ctx) {
  const auto& s = ctx.info().sii;
  const std::uint32_t ram_end = kRamStart + std::uint32_t{ctx.info().esc.ram_kib} * 1024u;
  struct Area {
    std::string name;
    std::uint32_t start, end;
  };
  std::vector<Area> areas;
  const bool configurable = s.has_coe() && s.general && (s.general->coe_details & (sii::kCoePdoAssign | sii::kCoePdoConfig)) != 0;
  for (std::size_t i = 0; i < s.sync_managers.size(); ++i) {
    const auto& sm = s.sync_managers[i];
    if (sm.length == 0 || sm.type == sii::kSmTypeUnused) continue;
    // An SM on the digital I/O register 0x0F00-0x0F03 (EL2004-style, ESC
    // Section I p.60) is the ESC's register, not a buffer in RAM.
    if (sm.start >= kDigitalOutputs && sm.start < kDigitalOutputsEnd) continue;
    // With PDO assignment/configuration a process-data SM's SII length is a
    // maximum the configurator sizes down (sii.sm_sizes_fit_pdos).
    const bool process = sm.type == sii::kSmTypeOutputs || sm.type == sii::kSmTypeInputs;
    if (process && configurable) continue;
    // An ESC in device emulation (SII word 0 bit 8 = 0x0141 bit 0, no µC:
    // Beckhoff EQ2339 packs 1-byte input SMs side by side) has no third-party
    // reader of the other buffers: count the length once.
    const std::uint32_t bytes = (s.pdi_control & kWord0DeviceEmulation) != 0 ? sm.length : sm_footprint(sm);
    areas.push_back({fmt::format("SM{}", i), sm.start, sm.start + bytes});
  }
  std::string problems;
  for (std::size_t i = 0; i < areas.size(); ++i) {
    if (areas[i].start < kRamStart || areas[i].end > ram_end) {
      problems += fmt::format("{} {}..{} outside RAM 0x1000..{}; ", areas[i].name, hex(areas[i].start, 4),
                              hex(areas[i].end - 1, 4), hex(ram_end - 1, 4));
    }
    for (std::size_t j = i + 1; j < areas.size(); ++j) {
      if (areas[i].start < areas[j].end && areas[j].start < areas[i].end) {
        problems += areas[i].name + " overlaps " + areas[j].name + "; ";
      }
    }
  }
  return CaseResult::compare("disjoint, inside RAM", problems_or(problems, "disjoint, inside RAM"));
}

CaseResult mailbox_sizes(Context& ctx) {
  const auto& s = ctx.info().sii;
  if (!s.has_mailbox()) return CaseResult::skip("no mailbox (SII words 0x18-0x1B zero)");
  std::string problems;
  const std::uint16_t need = (s.mailbox_protocols & sii::kProtoCoe) != 0 ? kMinCoeMailbox : kMailboxHeaderBytes + 1;
  if (s.rx_mailbox_size < need) problems += fmt::format("SM0 {} bytes < {}; ", s.rx_mailbox_size, need);
  if (s.tx_mailbox_size < need) problems += fmt::format("SM1 {} bytes < {}; ", s.tx_mailbox_size, need);
  if (s.rx_mailbox_offset < s.tx_mailbox_offset + s.tx_mailbox_size && s.tx_mailbox_offset < s.rx_mailbox_offset + s.rx_mailbox_size) {
    problems += "SM0 and SM1 overlap; ";
  }
  // Bootstrap mailbox (words 0x14-0x17): unused (all 0) or complete.
  const bool boot_any = s.boot_rx_size != 0 || s.boot_tx_size != 0 || s.boot_rx_offset != 0 || s.boot_tx_offset != 0;
  if (boot_any && (s.boot_rx_size < kMailboxHeaderBytes + 1 || s.boot_tx_size < kMailboxHeaderBytes + 1 ||
                   s.boot_rx_offset < kRamStart || s.boot_tx_offset < kRamStart)) {
    problems += fmt::format("bootstrap mailbox incomplete ({}/{} {}/{}); ", hex(s.boot_rx_offset, 4), s.boot_rx_size,
                            hex(s.boot_tx_offset, 4), s.boot_tx_size);
  }
  return CaseResult::compare("consistent", problems_or(problems, "consistent"));
}

CaseResult protocols_match_general(Context& ctx) {
  const auto& s = ctx.info().sii;
  if (!s.general) return CaseResult::failed("GENERAL category", "missing");
  auto show = [](bool coe, bool foe, bool eoe) {
    return fmt::format("CoE {} FoE {} EoE {}", coe ? "yes" : "no", foe ? "yes" : "no", eoe ? "yes" : "no");
  };
  const auto& g = *s.general;
  return CaseResult::compare(show((s.mailbox_protocols & sii::kProtoCoe) != 0, (s.mailbox_protocols & sii::kProtoFoe) != 0,
                                  (s.mailbox_protocols & sii::kProtoEoe) != 0),
                             show((g.coe_details & kDetailsEnable) != 0, (g.foe_details & kDetailsEnable) != 0,
                                  (g.eoe_details & kDetailsEnable) != 0));
}

CaseResult general_reserved(Context& ctx) {
  const auto& s = ctx.info().sii;
  if (!s.general) return CaseResult::failed("GENERAL category", "missing");
  const auto& g = *s.general;
  return CaseResult::compare("CoE details bits 7:6 = 0, flags bits 7:5 = 0",
                             fmt::format("CoE details bits 7:6 = {}, flags bits 7:5 = {}", (g.coe_details & kCoeDetailsReserved) >> 6,
                                         (g.flags & kGeneralFlagsReserved) >> 5));
}

CaseResult size_and_termination(Context& ctx) {
  const auto& img = ctx.info().sii_image;
  std::optional<std::size_t> end;
  (void)categories(img, end);
  const std::size_t size_bytes = (std::size_t{ctx.info().sii.size_word} + 1) * kSizeUnitBytes;
  const std::string want = fmt::format("END within {} bytes (word 0x3E = {}), version 1", size_bytes, ctx.info().sii.size_word);
  if (!end) return CaseResult::failed(want, "no END category (0xFFFF) in the image read");
  const std::size_t end_bytes = 2 * (*end + 1);
  if (end_bytes > size_bytes || ctx.info().sii.version != kSiiVersion) {
    return CaseResult::failed(want, fmt::format("END at byte {}, version {}", 2 * *end, ctx.info().sii.version));
  }
  return CaseResult::pass(want, want);
}

CaseResult checksum_word(Context& ctx) {
  const std::uint16_t w = word_at(ctx.info().sii_image, sii::kChecksum);
  const std::string want = "high byte 0x00, check not disabled (0x88A4)";
  if (w == kChecksumDisabled) return CaseResult::failed(want, "word 7 = 0x88A4 (checksum check disabled)");
  return CaseResult::compare(want, (w >> 8) == 0 ? want : "word 7 = " + hex(w, 4));
}

CaseResult dc_category_matches_esc(Context& ctx) {
  const auto& s = ctx.info().sii;
  if (s.dc_modes.empty()) return CaseResult::skip("no DC category (the device has no DC OpMode)");
  std::string problems;
  for (std::size_t i = 0; i < s.dc_modes.size(); ++i) {
    if (s.dc_modes[i].assign_activate != 0 && !ctx.info().esc.has_dc()) {
      problems += fmt::format("DC mode {} AssignActivate {}, 0x0008 bit 2 (DC) = 0; ", i, hex(s.dc_modes[i].assign_activate, 4));
    }
  }
  for (std::size_t i = 0; i < s.dc_modes.size(); ++i) {
    const std::uint16_t aa = s.dc_modes[i].assign_activate;
    if ((aa & ~kAssignActivateDefined) != 0) {
      problems += fmt::format("DC mode {} AssignActivate {} sets undefined 0x0980 bits; ", i, hex(aa, 4));
    }
    if ((aa & kAssignActivateSync0) != 0 && (aa & kAssignActivateUnit) == 0) {
      problems += fmt::format("DC mode {} AssignActivate {} generates SYNC0 without activating the SYNC unit (0x0981 bit 0); ", i, hex(aa, 4));
    }
  }
  return CaseResult::compare("consistent", problems_or(problems, "consistent"));
}

// Every SII PDO entry names an object entry of the dictionary with the same
// data type and bit length (ETG.2010 TXPDO/RXPDO entries; ETG.1000.6 §5.6.3).
CaseResult pdo_entries_in_od(Context& ctx, bool compare_types) {
  const auto& s = ctx.info().sii;
  if (s.tx_pdos.empty() && s.rx_pdos.empty()) return CaseResult::skip("SII has no PDO categories");
  if (auto r = ctx.go_to(AlState::PreOp); !r) return CaseResult::failed("reach PreOp", r.error());
  if (!s.has_coe()) return CaseResult::skip("no CoE (no dictionary to compare with)");
  const auto& g = s.general;
  if (!g || (g->coe_details & sii::kCoeSdoInfo) == 0) return CaseResult::skip("no SDO information (SII CoE details)");
  CoeClient coe = ctx.coe();
  std::string problems;
  std::size_t checked = 0;
  for (const auto* pdos : {&s.rx_pdos, &s.tx_pdos}) {
    for (const auto& p : *pdos) {
      for (const auto& e : p.entries) {
        if (e.index == 0) continue;  // gap
        ++checked;
        auto d = coe.entry_description(e.index, e.subindex);
        if (!d) {
          if (!compare_types) problems += fmt::format("{}:{} {}; ", hex(e.index, 4), e.subindex, describe_sdo(d.error()));
          continue;
        }
        // A mapping may take fewer bits than the object holds (Beckhoff maps
        // 16 bits of some 32-bit entries); more bits than it has, or another
        // type, is wrong.
        if (compare_types && ((d->data_type & 0xFF) != e.data_type || e.bit_length > d->bit_length)) {
          problems += fmt::format("{}:{} SII type {} {} bits, OD type {} {} bits; ", hex(e.index, 4), e.subindex,
                                  hex(e.data_type, 2), e.bit_length, hex(d->data_type, 4), d->bit_length);
        }
        if (problems.size() > 300) break;
      }
    }
  }
  const std::string ok = fmt::format("{} entries found in the OD", checked);
  return CaseResult::compare(ok, problems_or(problems, ok));
}

}  // namespace

std::vector<Case> sii_rule_cases() {
  return {
      {"sii.end_within_size", "ETG.2010 / ETG.1000.6 §5.4: category list ends with 0xFFFF inside the EEPROM size of word 0x3E; version word 0x3F = 1 (sii-eeprom.md §1, §3, §5 #5-#7)", size_and_termination},
      {"sii.string_indices", "ETG.2010 STRINGS: every name index (GENERAL, PDOs, entries, DC modes) <= number of strings (sii-eeprom.md §3.1)", string_indices},
      {"sii.checksum_word", "ESC Section I p.93 / ETG.1000.6 §5.4: word 7 high byte 0, not the debug value 0x88A4 (sii-eeprom.md §1-§2)", checksum_word},
      {"sii.syncm_types", "ETG.2010 SYNCM: type 0-4; with a mailbox SM0 = 1 (mailbox out), SM1 = 2 (mailbox in) (sii-eeprom.md §3.4)", syncm_types},
      {"sii.pdo_sync_managers", "ETG.2010 TXPDO/RXPDO: RxPDO 0x1600-0x17FF on an outputs SM (type 3), TxPDO 0x1A00-0x1BFF on an inputs SM (type 4) (sii-eeprom.md §3.4, §3.6)", pdo_sync_managers},
      {"sii.sm_sizes_fit_pdos", "ETG.2000 Sm DefaultSize / ETG.2010 SYNCM length = the default PDOs' bytes on that SM, for fixed process data (no PDO assign/config) (sii-eeprom.md §3.4, §3.6)", sm_sizes_fit_pdos},
      {"sii.fmmu_usage", "ETG.2010 FMMU category: usage 0-3, an outputs/inputs FMMU when RxPDOs/TxPDOs exist, no more than 0x0004 FMMUs (sii-eeprom.md §3.3)", fmmu_usage},
      {"sii.sm_areas_in_ram", "ESC Section I p.60/p.62 / ETG.2010 SYNCM: SM areas (x3 in 3-buffer mode; process-data SMs only for fixed PDOs) disjoint and inside the process RAM of 0x0006; SMs on the digital I/O register 0x0F00 exempt (esc-registers.md §7.1)", sm_areas},
      {"sii.mailbox_sizes", "ETG.1000.4 §5.6 / ETG.1000.6 §5.6.2: SM0/SM1 hold an expedited SDO (16 bytes) with CoE, do not overlap, bootstrap words 0x14-0x17 all 0 or complete (sii-eeprom.md §1)", mailbox_sizes},
      {"sii.protocols_match_general", "ETG.2010 GENERAL CoE/FoE/EoE details bit 0 equal word 0x1C protocol bits (sii-eeprom.md §3.2, §5 #4)", protocols_match_general},
      {"sii.general_reserved_bits", "ETG.2010 GENERAL: CoE details bits 7:6 and flags bits 7:5 reserved 0 (sii-eeprom.md §3.2)", general_reserved},
      {"sii.dc_category_matches_esc", "ETG.2010 DC category: an OpMode with an AssignActivate needs an ESC with DC (0x0008 bit 2); AssignActivate sets only defined 0x0980 bits and SYNC0 only with the unit active (0x0981 bits 0/1; ESC Section II 0x0980-0x0981; sii-eeprom.md §3.7, esc-registers.md §10)", dc_category_matches_esc},
      {"sii.pdo_entries_exist", "ETG.2010 TXPDO/RXPDO entries name objects of the dictionary (SDO information entry description, ETG.1000.6 §5.6.3; sii-eeprom.md §3.6)",
       [](Context& ctx) { return pdo_entries_in_od(ctx, false); }},
      {"sii.pdo_entry_types_match_od", "ETG.2010 PDO entry data type equals, and its bit length does not exceed, the dictionary's entry description (ETG.1000.6 §5.6.3; sii-eeprom.md §3.6)",
       [](Context& ctx) { return pdo_entries_in_od(ctx, true); }},
  };
}

}  // namespace ecat::master::conformance
