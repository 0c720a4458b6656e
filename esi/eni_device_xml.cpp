// A device file (docs/device-format.md) for an ENI slave that has no ESI: the
// ENI's identity, mailbox, sync managers and PDOs, and a dictionary made of
// what the ENI shows of the device (docs/twins.md "Networks from an ENI"):
//  * every object a PDO entry maps (type from the entry's DataType, else from
//    its bit length; outputs rw + RxPDO-mappable, inputs ro + TxPDO-mappable);
//  * every PDO a sync manager lists or a 1C1xh InitCmd assigns; a PDO the ENI
//    does not describe is made empty (its content is unknown), with a warning;
//  * every object outside the communication area (1000h-1FFFh) that a CoE
//    download InitCmd writes, sized by the data written, rw.
// The file then goes through the same loader as every device file, so the
// derived objects (1018h, 1C00h, 1C1xh, 16xxh/1Axxh) follow from it.
#include <algorithm>
#include <map>
#include <set>

#include <fmt/format.h>

#include "common/le.hpp"
#include "esi/device_values.hpp"
#include "esi/eni_devices.hpp"
#include "esi/xml_chars.hpp"
#include "od/data_type.hpp"

namespace ecat::esi {
namespace {

// ETG.1000.6 §5.6.7: object areas.
constexpr std::uint16_t kCommunicationFirst = 0x1000;
constexpr std::uint16_t kCommunicationLast = 0x1FFF;
constexpr std::uint16_t kRxPdoFirst = 0x1600;
constexpr std::uint16_t kRxPdoLast = 0x17FF;
constexpr std::uint16_t kTxPdoFirst = 0x1A00;
constexpr std::uint16_t kTxPdoLast = 0x1BFF;
constexpr std::uint16_t kSmAssignFirst = 0x1C10;
constexpr std::uint16_t kSmAssignLast = 0x1C2F;
// ETG.1000.4 register map: SM n configuration at 0x0800 + 8n (start, length, control).
constexpr std::uint16_t kSmRegisterFirst = 0x0800;
constexpr std::uint16_t kSmRegisterSize = 8;
constexpr unsigned kSmCount = 8;
// ETG.1000.4 §8.2: SM register block: start (0), length (2), control (4).
constexpr std::uint8_t kSmLengthOffset = 2;
constexpr std::uint8_t kSmControlOffset = 4;
// ETG.1000.4 Table 13: the write commands a master configures registers with.
constexpr std::uint8_t kCmdApwr = 2;
constexpr std::uint8_t kCmdFpwr = 5;
constexpr std::uint8_t kCmdBwr = 8;
// ETG.1000.4 §8.2.1 defaults of the SM control byte.
constexpr unsigned kControlMailboxOut = 0x26;
constexpr unsigned kControlMailboxIn = 0x22;
constexpr unsigned kControlOutputs = 0x64;
constexpr unsigned kControlInputs = 0x20;
// Process RAM of the emulated ESC starts at 0x1000; 3 buffers per buffered SM.
constexpr unsigned kProcessRamStart = 0x1000;
constexpr unsigned kProcessRamMax = 0xF000;
constexpr unsigned kDefaultRamSize = 8192;
constexpr unsigned kBuffers = 3;
constexpr unsigned kPlacementAlign = 0x100;
constexpr unsigned kBitsPerByte = 8;
// In a complete access to subindex 0, SI0 takes 16 bits (8 data + 8 padding).
constexpr std::size_t kCompleteAccessSi0Bytes = 2;
constexpr std::size_t kMappingBytes = 4;
constexpr std::size_t kAssignBytes = 2;
constexpr unsigned kMaxBitType = 8;
constexpr unsigned kMaxIntegerBits = 64;
// A PDO mapping entry (ETG.1000.6 §5.6.7.4.7): index << 16 | subindex << 8 | bits.
constexpr unsigned kMappingIndexShift = 16;
constexpr unsigned kMappingSubShift = 8;
constexpr std::uint32_t kMappingBitsMask = 0xFF;

std::string escape(std::string_view raw) {
  std::string out;
  const std::string text = xml_safe_text(raw);  // no character XML 1.0 forbids (issue 32)
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default:
        if (static_cast<unsigned char>(c) >= 0x20 || c == '\t') out.push_back(c);
    }
  }
  return out;
}

bool is_rx_pdo(std::uint16_t index) { return index >= kRxPdoFirst && index <= kRxPdoLast; }
bool is_tx_pdo(std::uint16_t index) { return index >= kTxPdoFirst && index <= kTxPdoLast; }

struct SynthEntry {
  std::string type;  // CiA 301 name
  unsigned length = 0;  // bytes, for OCTET_STRING
  std::string name;
  bool rx = false, tx = false, written = false;
  SourcePos line;
};

struct SmPlan {
  std::string type;  // MailboxOut MailboxIn Outputs Inputs
  std::optional<unsigned> start, size, control;
  unsigned max_size = 0;
  SourcePos line;
};

struct PdoPlan {
  EniPdo pdo;
  unsigned max_entries = 0;
  bool synthesised = false;
};

// The CiA 301 type of an entry of `bits` bits with the ESI type name `esi`.
SynthEntry entry_type(const std::string& esi, unsigned bits) {
  SynthEntry e;
  if (auto t = od::from_esi_base_name(esi); t && entry_bit_length(*t, 0) == bits) {
    e.type = std::string(od::canopen_name(*t));
    return e;
  }
  if (bits >= 1 && bits <= kMaxBitType && bits != kBitsPerByte) {
    e.type = fmt::format("BIT{}", bits);
  } else if (bits % kBitsPerByte == 0 && bits <= kMaxIntegerBits && bits > 0) {
    e.type = fmt::format("UNSIGNED{}", bits);
  } else {
    e.type = "OCTET_STRING";
    e.length = (bits + kBitsPerByte - 1) / kBitsPerByte;
  }
  return e;
}

class Builder {
 public:
  Builder(const EniSlave& s, std::vector<EsiWarning>* warnings) : s_(s), warnings_(warnings) {}

  EniDeviceXml build() {
    plan_sync_managers();
    plan_pdos();
    plan_objects();
    place_sync_managers();
    write();
    return std::move(out_);
  }

 private:
  void warn(SourcePos line, std::string element, std::string message) {
    if (warnings_) warnings_->push_back({std::move(element), line, std::move(message)});
  }

  // Register InitCmds that write a sync manager's configuration (0x0800+8n).
  void sm_registers() {
    for (const auto& c : s_.init_cmds) {
      if (c.cmd != kCmdApwr && c.cmd != kCmdFpwr && c.cmd != kCmdBwr) continue;
      if (c.ado < kSmRegisterFirst || c.ado >= kSmRegisterFirst + kSmCount * kSmRegisterSize) continue;
      const unsigned first = (c.ado - kSmRegisterFirst) / kSmRegisterSize;
      if ((c.ado - kSmRegisterFirst) % kSmRegisterSize != 0) continue;
      for (unsigned k = 0; (k + 1) * kSmRegisterSize <= c.data.size() && first + k < kSmCount; ++k) {
        const std::uint8_t* p = c.data.data() + k * kSmRegisterSize;
        RegisterSm r{load_le<std::uint16_t>(p), load_le<std::uint16_t>(p + kSmLengthOffset), p[kSmControlOffset], c.line};
        if (r.start != 0 || r.length != 0) reg_sm_[first + k] = r;
      }
    }
  }

  void plan_sync_managers() {
    sm_registers();
    if (s_.mailbox) {
      const auto& m = *s_.mailbox;
      sms_[0] = SmPlan{"MailboxOut", m.out_start, m.out_length, kControlMailboxOut, 0, m.line};
      sms_[1] = SmPlan{"MailboxIn", m.in_start, m.in_length, kControlMailboxIn, 0, m.line};
    }
    for (const auto& sm : s_.sync_managers) {
      SmPlan p{sm.outputs ? "Outputs" : "Inputs", sm.start, std::nullopt, sm.control, 0, sm.line};
      if (sms_.contains(sm.number) && sms_[sm.number].type.starts_with("Mailbox")) {
        throw_at(sm.line, fmt::format("Sm{} is the mailbox's sync manager and cannot carry process data", sm.number));
      }
      sms_[sm.number] = p;
    }
    for (auto& [n, p] : sms_) {
      auto r = reg_sm_.find(n);
      if (r == reg_sm_.end()) continue;
      if (!p.start) p.start = r->second.start;
      if (!p.control || p.type.starts_with("Mailbox")) p.control = r->second.control;
    }
  }

  [[noreturn]] void throw_at(SourcePos line, std::string message) const {
    throw EniSynthFailure{line, std::move(message)};
  }

 public:
  struct EniSynthFailure {
    SourcePos line;
    std::string message;
  };

 private:
  void add_pdo(const EniPdo& p) {
    if (pdos_.contains(p.index)) {
      warn(p.line, p.rx ? "RxPdo" : "TxPdo", fmt::format("PDO #x{:04X} described twice; the first is used", p.index));
      return;
    }
    pdos_[p.index] = PdoPlan{p, static_cast<unsigned>(p.entries.size()), false};
  }

  void need_pdo(std::uint16_t index, SourcePos line, std::optional<unsigned> sm) {
    if (pdos_.contains(index)) return;
    if (!is_rx_pdo(index) && !is_tx_pdo(index)) {
      throw_at(line, fmt::format("#x{:04X} is not a PDO index (RxPDO 1600h-17FFh, TxPDO 1A00h-1BFFh)", index));
    }
    EniPdo p;
    p.rx = is_rx_pdo(index);
    p.index = index;
    p.name = fmt::format("PDO {:04X}h", index);
    p.line = line;
    if (sm) p.sm = static_cast<std::uint8_t>(*sm);
    pdos_[index] = PdoPlan{p, 0, true};
    warn(line, "Pdo", fmt::format("PDO #x{:04X} is assigned but the ENI does not describe its entries; "
                                  "it is made with none",
                                  index));
  }

  void plan_pdos() {
    for (const auto& p : s_.rx_pdos) add_pdo(p);
    for (const auto& p : s_.tx_pdos) add_pdo(p);
    // The ENI's assignment (ProcessData/SmN/Pdo) is the default assignment.
    bool any_listed = false;
    for (const auto& sm : s_.sync_managers) {
      for (auto index : sm.pdos) {
        any_listed = true;
        need_pdo(index, sm.line, std::nullopt);
        assigned_[index] = sm.number;
      }
    }
    if (!any_listed) {
      for (const auto& [index, plan] : pdos_) {
        if (plan.pdo.sm) assigned_[index] = *plan.pdo.sm;
      }
    }
    // What the CoE InitCmds assign and map.
    for (const auto& c : s_.coe_init_cmds) {
      if (!c.download) continue;
      if (c.index >= kSmAssignFirst && c.index <= kSmAssignLast) {
        const unsigned sm = c.index - kSmAssignFirst;
        std::vector<std::uint16_t> listed;
        if (c.complete_access) {
          for (std::size_t o = kCompleteAccessSi0Bytes; o + kAssignBytes <= c.data.size(); o += kAssignBytes) {
            listed.push_back(load_le<std::uint16_t>(c.data.data() + o));
          }
        } else if (c.subindex > 0 && c.data.size() >= kAssignBytes) {
          listed.push_back(load_le<std::uint16_t>(c.data.data()));
        }
        for (auto index : listed) {
          need_pdo(index, c.line, sm);
          if (!sms_.contains(sm)) {
            sms_[sm] = SmPlan{is_rx_pdo(index) ? "Outputs" : "Inputs", std::nullopt, std::nullopt, std::nullopt, 0,
                              c.line};
            if (auto r = reg_sm_.find(sm); r != reg_sm_.end()) {
              sms_[sm].start = r->second.start;
              sms_[sm].control = r->second.control;
            }
          }
        }
      } else if (is_rx_pdo(c.index) || is_tx_pdo(c.index)) {
        need_pdo(c.index, c.line, std::nullopt);
        auto& plan = pdos_[c.index];
        std::vector<std::uint32_t> words;
        if (c.complete_access) {
          for (std::size_t o = kCompleteAccessSi0Bytes; o + kMappingBytes <= c.data.size(); o += kMappingBytes) {
            words.push_back(load_le<std::uint32_t>(c.data.data() + o));
          }
          plan.max_entries = std::max<unsigned>(plan.max_entries, static_cast<unsigned>(words.size()));
        } else if (c.subindex > 0 && c.data.size() == kMappingBytes) {
          words.push_back(load_le<std::uint32_t>(c.data.data()));
          plan.max_entries = std::max<unsigned>(plan.max_entries, c.subindex);
        }
        for (auto w : words) mapped_by_cmd_.push_back({w, plan.pdo.rx, c.line, c.index});
      }
    }
  }

  void note_object(std::uint16_t index, std::uint8_t sub, SynthEntry e) {
    auto& subs = objects_[index];
    auto it = subs.find(sub);
    if (it == subs.end()) {
      subs.emplace(sub, std::move(e));
      return;
    }
    it->second.rx = it->second.rx || e.rx;
    it->second.tx = it->second.tx || e.tx;
    it->second.written = it->second.written || e.written;
  }

  // The ESI import's policy for a PDO entry of an object the file does not
  // describe (docs/twins.md "Import policy", issue 32): an object outside the
  // communication area is made as process data (an ENI describes no
  // dictionary, so silently); one inside it (Elmo drives map 1002h, the
  // manufacturer status register) too, with a warning, unless the loader
  // derives that object from the SII (1018h, 1C00h, 1C1xh, 16xxh/1Axxh,
  // 1C32h/1C33h).
  bool comm_area_process_data(std::uint16_t index, std::uint8_t sub, std::uint16_t pdo, unsigned bits, SourcePos line) {
    if (index < kCommunicationFirst || index > kCommunicationLast) return true;
    constexpr std::uint16_t kIdentity = 0x1018, kSmCommType = 0x1C00, kSyncOutputs = 0x1C32, kSyncInputs = 0x1C33;
    const bool derived = index == kIdentity || index == kSmCommType || (index >= kSmAssignFirst && index <= kSmAssignLast) ||
                         is_rx_pdo(index) || is_tx_pdo(index) || index == kSyncOutputs || index == kSyncInputs;
    if (derived) return false;
    if (!objects_.contains(index) || !objects_[index].contains(sub)) {
      warn(line, "Entry", fmt::format("PDO #x{:04X} maps {:04X}h:{:02X}, an object of the communication area the ENI "
                                      "does not describe; object created as process data ({} bits)",
                                      pdo, index, sub, bits));
    }
    return true;
  }

  void plan_objects() {
    for (const auto& [index, plan] : pdos_) {
      for (const auto& en : plan.pdo.entries) {
        if (en.index == 0) continue;  // a gap
        SynthEntry e = entry_type(en.data_type, en.bit_length);
        e.name = en.name.empty() ? fmt::format("Object {:04X}h:{:02X}h", en.index, en.subindex) : en.name;
        e.rx = plan.pdo.rx;
        e.tx = !plan.pdo.rx;
        e.line = en.line;
        if (!comm_area_process_data(en.index, en.subindex, plan.pdo.index, en.bit_length, en.line)) continue;
        note_object(en.index, en.subindex, std::move(e));
      }
    }
    for (const auto& m : mapped_by_cmd_) {
      const auto index = static_cast<std::uint16_t>(m.word >> kMappingIndexShift);
      const auto sub = static_cast<std::uint8_t>(m.word >> kMappingSubShift);
      const auto bits = static_cast<unsigned>(m.word & kMappingBitsMask);
      if (index == 0) continue;
      if (!comm_area_process_data(index, sub, m.pdo, bits, m.line)) continue;
      SynthEntry e = entry_type("", bits);
      e.name = fmt::format("Object {:04X}h:{:02X}h", index, sub);
      e.rx = m.rx;
      e.tx = !m.rx;
      e.line = m.line;
      note_object(index, sub, std::move(e));
    }
    for (const auto& c : s_.coe_init_cmds) {
      if (!c.download || (c.index >= kCommunicationFirst && c.index <= kCommunicationLast)) continue;
      if (c.complete_access) {
        if (!objects_.contains(c.index)) {
          warn(c.line, "InitCmd", fmt::format("complete access to #x{:04X}, an object the ENI does not describe: "
                                              "its structure is unknown, it is not made",
                                              c.index));
        }
        continue;
      }
      if (objects_.contains(c.index) && objects_[c.index].contains(c.subindex)) {
        objects_[c.index][c.subindex].written = true;
        continue;
      }
      SynthEntry e = entry_type("", static_cast<unsigned>(c.data.size() * kBitsPerByte));
      e.name = c.comment.empty() ? fmt::format("Object {:04X}h:{:02X}h", c.index, c.subindex) : c.comment;
      e.written = true;
      e.line = c.line;
      note_object(c.index, c.subindex, std::move(e));
    }
  }

  unsigned pdo_bytes(bool rx, bool assigned_only, std::optional<unsigned> sm) const {
    unsigned bits = 0;
    for (const auto& [index, plan] : pdos_) {
      if (plan.pdo.rx != rx) continue;
      auto a = assigned_.find(index);
      if (assigned_only && (a == assigned_.end() || (sm && a->second != *sm))) continue;
      for (const auto& e : plan.pdo.entries) bits += e.bit_length;
    }
    return (bits + kBitsPerByte - 1) / kBitsPerByte;
  }

  // Process-data SMs without a start address go after everything placed.
  void place_sync_managers() {
    unsigned end = kProcessRamStart;
    for (auto& [n, p] : sms_) {
      if (p.type == "Outputs" || p.type == "Inputs") {
        const unsigned all = pdo_bytes(p.type == "Outputs", false, std::nullopt);
        p.max_size = all;
      }
      if (p.start) {
        const unsigned len = p.size.value_or(p.max_size);
        end = std::max(end, *p.start + len * (p.type.starts_with("Mailbox") ? 1 : kBuffers));
      }
    }
    for (auto& [n, p] : sms_) {
      if (p.start) continue;
      end = (end + kPlacementAlign - 1) / kPlacementAlign * kPlacementAlign;
      p.start = end;
      end += std::max(p.max_size, 1u) * kBuffers;
    }
    ram_end_ = end;
    if (ram_end_ - kProcessRamStart > kProcessRamMax) {
      throw_at(s_.line, fmt::format("the sync managers need {} bytes of process RAM, more than the ESC's {}",
                                    ram_end_ - kProcessRamStart, kProcessRamMax));
    }
  }

  void line(std::string text, SourcePos eni_line) {
    out_.xml += text;
    out_.xml += '\n';
    out_.eni_lines.push_back(eni_line);
  }

  void write() {
    const EniSlave& s = s_;
    line("<?xml version=\"1.0\" encoding=\"UTF-8\"?>", s.line);
    line("<Device formatVersion=\"1\">", s.line);
    line("  <Include href=\"../profiles/cia301.xml\"/>", s.line);
    const std::string name = escape(s.name.empty() ? fmt::format("ENI slave {:08X}", s.product_code) : s.name);
    line(fmt::format("  <Identity vendorId=\"#x{:08X}\" productCode=\"#x{:08X}\" revision=\"#x{:08X}\" "
                     "serial=\"{}\" name=\"{}\" type=\"{}\"/>",
                     s.vendor_id, s.product_code, s.revision, s.serial, name, name),
         s.info_line);
    unsigned ram = kDefaultRamSize;
    while (kProcessRamStart + ram < ram_end_) ram *= 2;
    line(fmt::format("  <Esc ramSize=\"{}\"/>", std::min(ram, kProcessRamMax)), s.line);
    const auto& m = s.mailbox;
    line(fmt::format("  <Mailbox coe=\"{}\" foe=\"{}\" eoe=\"{}\" soe=\"{}\" sdoInfo=\"true\" pdoAssign=\"true\" "
                     "pdoConfig=\"true\" completeAccess=\"true\" segmentedSdo=\"true\"/>",
                     m && m->coe, m && m->foe, m && m->eoe, m && m->soe),
         m ? m->line : s.line);
    if (!sms_.empty()) {
      line("  <SyncManagers>", s.line);
      for (const auto& [n, p] : sms_) {
        std::string attrs = fmt::format("index=\"{}\" type=\"{}\" start=\"#x{:04X}\"", n, p.type, *p.start);
        if (p.size) attrs += fmt::format(" size=\"{}\"", *p.size);
        if (!p.type.starts_with("Mailbox") && p.max_size > 0) attrs += fmt::format(" maxSize=\"{}\"", p.max_size);
        const unsigned control = p.control.value_or(p.type == "Outputs" ? kControlOutputs : kControlInputs);
        attrs += fmt::format(" control=\"#x{:02X}\"", control);
        line(fmt::format("    <Sm {}/>", attrs), p.line);
      }
      line("  </SyncManagers>", s.line);
    }
    line("  <Fmmus>", s.line);
    line("    <Fmmu usage=\"Outputs\"/>", s.line);
    line("    <Fmmu usage=\"Inputs\"/>", s.line);
    if (m) line("    <Fmmu usage=\"MailboxState\"/>", s.line);
    line("  </Fmmus>", s.line);
    write_objects();
    for (const auto& [index, plan] : pdos_) write_pdo(plan);
    line("</Device>", s.line);
  }

  static std::string access_attrs(const SynthEntry& e) {
    const char* pdo = e.rx && e.tx ? "rxtx" : e.rx ? "rx" : e.tx ? "tx" : "none";
    const bool rw = e.rx || e.written;
    return fmt::format("access=\"{}\" pdo=\"{}\"", rw ? "rw" : "ro", pdo);
  }

  static std::string type_attrs(const SynthEntry& e) {
    std::string out = fmt::format("type=\"{}\"", e.type);
    if (e.length > 0) out += fmt::format(" length=\"{}\"", e.length);
    return out;
  }

  void write_objects() {
    if (objects_.empty()) return;
    line("  <Objects>", s_.line);
    for (const auto& [index, subs] : objects_) {
      const bool var = subs.size() == 1 && subs.begin()->first == 0;
      const SourcePos first_line = subs.begin()->second.line;
      if (var) {
        const SynthEntry& e = subs.begin()->second;
        line(fmt::format("    <Object index=\"#x{:04X}\" name=\"{}\" {} {}/>", index, escape(e.name), type_attrs(e),
                         access_attrs(e)),
             e.line);
        continue;
      }
      if (subs.contains(0)) {
        throw_at(first_line, fmt::format("#x{:04X} is used both as a variable (subindex 0) and with subindices",
                                         index));
      }
      line(fmt::format("    <Object index=\"#x{:04X}\" name=\"Object {:04X}h\" code=\"RECORD\">", index, index),
           first_line);
      for (const auto& [sub, e] : subs) {
        line(fmt::format("      <Entry sub=\"{}\" name=\"{}\" {} {}/>", sub, escape(e.name), type_attrs(e),
                         access_attrs(e)),
             e.line);
      }
      line("    </Object>", first_line);
    }
    line("  </Objects>", s_.line);
  }

  void write_pdo(const PdoPlan& plan) {
    const EniPdo& p = plan.pdo;
    std::string attrs = fmt::format("index=\"#x{:04X}\" name=\"{}\"", p.index, escape(p.name));
    if (auto a = assigned_.find(p.index); a != assigned_.end()) attrs += fmt::format(" sm=\"{}\"", a->second);
    if (p.fixed) attrs += " fixed=\"true\"";
    const unsigned max_entries = std::max<unsigned>(plan.max_entries, static_cast<unsigned>(p.entries.size()));
    if (max_entries > p.entries.size()) attrs += fmt::format(" maxEntries=\"{}\"", max_entries);
    const char* element = p.rx ? "RxPdo" : "TxPdo";
    if (p.entries.empty()) {
      line(fmt::format("  <{} {}/>", element, attrs), p.line);
      return;
    }
    line(fmt::format("  <{} {}>", element, attrs), p.line);
    for (const auto& e : p.entries) {
      line(fmt::format("    <Entry index=\"#x{:04X}\" sub=\"{}\" bits=\"{}\"/>", e.index, e.subindex, e.bit_length),
           e.line);
    }
    line(fmt::format("  </{}>", element), p.line);
  }

  struct RegisterSm {
    std::uint16_t start = 0;
    std::uint16_t length = 0;
    std::uint8_t control = 0;
    SourcePos line;
  };
  struct MappedWord {
    std::uint32_t word;
    bool rx;
    SourcePos line;
    std::uint16_t pdo;
  };

  const EniSlave& s_;
  std::vector<EsiWarning>* warnings_;
  std::map<unsigned, RegisterSm> reg_sm_;
  std::map<unsigned, SmPlan> sms_;
  std::map<std::uint16_t, PdoPlan> pdos_;
  std::map<std::uint16_t, unsigned> assigned_;  // PDO -> SM (default assignment)
  std::vector<MappedWord> mapped_by_cmd_;
  std::map<std::uint16_t, std::map<std::uint8_t, SynthEntry>> objects_;
  unsigned ram_end_ = kProcessRamStart;
  EniDeviceXml out_;
};

}  // namespace

EniDeviceXml eni_device_xml(const EniSlave& slave, std::vector<EsiWarning>* warnings) {
  try {
    return Builder(slave, warnings).build();
  } catch (const Builder::EniSynthFailure& f) {
    // Reported by eni_devices as a LoadError at the ENI line.
    EniDeviceXml failed;
    failed.xml.clear();
    failed.eni_lines = {f.line};
    failed.error = f.message;
    return failed;
  }
}

}  // namespace ecat::esi
