// Import policy for digital twins (docs/twins.md "Import policy"): where a
// vendor ESI contradicts itself, the twin behaves towards a master as the real
// device does. What the master reads from the SII (the Sm elements, the
// RxPdo/TxPdo lists with their Sm attributes, the identity) decides the
// dictionary objects that describe the same thing: 1018h (ETG.1000.6 §5.4:
// SII words 8h-Fh equal 1018h:01-04), 1C00h (ETG.1000.6 §5.6.7.4.1, the SM
// communication types), 1C12h/1C13h (default PDO assignment, ETG.2010 TXPDO/
// RXPDO categories) and 16xxh/1Axxh (PDO mapping). Each repair is one warning
// naming the object and its line; nothing is changed silently.
#include <algorithm>
#include <cctype>
#include <map>

#include <fmt/format.h>

#include "esi/esi_reader_context.hpp"
#include "esi/sii_layout.hpp"
#include "esi/sii_writer.hpp"
#include "esi/xml_chars.hpp"
#include "od/firmware.hpp"
#include "od/type_of_bits.hpp"

namespace ecat::esi {
namespace {

constexpr std::uint16_t kIdentityObject = 0x1018;
constexpr std::uint16_t kSmCommType = 0x1C00;
constexpr std::uint16_t kSmAssignFirst = 0x1C10;
constexpr std::uint16_t kRxMappingFirst = 0x1600, kRxMappingLast = 0x17FF;
constexpr std::uint16_t kTxMappingFirst = 0x1A00, kTxMappingLast = 0x1BFF;
constexpr unsigned kMappingIndexShift = 16, kMappingSubShift = 8;
constexpr std::uint8_t kBitsPerByte = 8;
constexpr std::uint8_t kIdentityEntries = 4;        // 1018h:01-04 (CiA 301)
constexpr std::size_t kAssignBytes = 2;             // 1C1xh entries: UNSIGNED16 PDO indices
constexpr std::size_t kSmTypeBytes = 1;             // 1C00h entries: UNSIGNED8 SM types
constexpr std::size_t kMappingBytes = 4;            // 16xxh/1Axxh entries: UNSIGNED32
// The highest subindex (8 bits): a subindex 0 that says more (a fuzzed UDINT
// SI0 of 4,294,967,295 made the repairs list 2^32 entries) names no more.
constexpr std::uint64_t kHighestSubindex = 0xFF;
constexpr std::uint16_t kIdentityBits = 32;

std::string hex_value(const od::Value& v) {
  std::string s;
  for (auto it = v.rbegin(); it != v.rend(); ++it) s += fmt::format("{:02X}", *it);
  return s.empty() ? "(none)" : "#x" + s;
}

od::Value le_of(std::uint64_t v, std::size_t bytes) {
  od::Value out(bytes);
  for (std::size_t i = 0; i < bytes; ++i) out[i] = static_cast<std::uint8_t>(v >> (kBitsPerByte * i));
  return out;
}

std::uint64_t value_of(const od::Value& v) {
  std::uint64_t out = 0;
  for (std::size_t i = 0; i < v.size() && i < sizeof(out); ++i) out |= std::uint64_t{v[i]} << (kBitsPerByte * i);
  return out;
}

// The type a PDO entry without a dictionary object gets, by its bit length.
std::optional<od::DataType> type_for_bits(od::DataType named, unsigned bits) {
  if (od::fixed_bit_size(named) == bits) return named;
  return od::unsigned_type_of_bits(bits);
}

std::uint8_t sm_type_code(od::SmType t) { return static_cast<std::uint8_t>(t); }

class Repairer {
 public:
  Repairer(const pugi::xml_node& device, const EsiContext& ctx, od::DeviceDescription& d)
      : ctx_(ctx), d_(d), device_(device), device_line_(ctx.line(device)) {}

  void run() {
    repair_sm_direction();
    renumber_out_of_range_pdos();
    repair_process_sm_sizes();
    repair_mailbox_sm_sizes();
    adopt_dictionary_assignment();
    shrink_fixed_process_sms();
    create_missing_pdo_objects();
    repair_identity();
    repair_sm_types();
    repair_assignments();
    repair_mapping_entry_types(ctx_, d_);
    repair_mappings();
    warn_pdi_type_with_mailbox();
    repair_eeprom_size();
    repair_forbidden_characters();
  }

 private:
  SourcePos line_of(const od::Object& o) const { return o.source_line ? SourcePos{o.source_line} : device_line_; }
  void warn(const od::Object& o, std::string message) const { ctx_.warn_at("Object", line_of(o), std::move(message)); }

  // Sets entry `sub` of `o` to `value` (written as `bytes` bytes), growing a
  // too-short object with entries shaped like its last one. False if the
  // object cannot hold the entry.
  static bool set_sub(od::Object& o, std::uint8_t sub, std::uint64_t value, std::size_t bytes, od::DataType type) {
    if (od::Entry* e = o.find(sub)) {
      e->default_value = le_of(value, (e->bit_length + kBitsPerByte - 1) / kBitsPerByte);
      return true;
    }
    if (o.code == od::ObjectCode::Var || o.entries.empty()) return false;
    od::Entry e = o.entries.back().subindex == 0 && o.entries.size() == 1 ? od::Entry{} : o.entries.back();
    if (o.entries.size() == 1) {
      e.type = type;
      e.bit_length = static_cast<std::uint16_t>(bytes * kBitsPerByte);
      e.access = o.entries.front().access;
    }
    e.subindex = sub;
    e.name = fmt::format("SubIndex {:03}", sub);
    e.default_value = le_of(value, (e.bit_length + kBitsPerByte - 1) / kBitsPerByte);
    e.min_value.clear();
    e.max_value.clear();
    auto at = std::lower_bound(o.entries.begin(), o.entries.end(), sub,
                               [](const od::Entry& x, std::uint8_t s) { return x.subindex < s; });
    o.entries.insert(at, std::move(e));
    return true;
  }

  // Writes a list object (SI0 = count, subs 1..n = values, the rest 0) when
  // it differs; returns the old and new contents for the warning.
  bool rewrite_list(od::Object& o, const std::vector<std::uint64_t>& values, std::size_t bytes, od::DataType type,
                    std::string& was) {
    std::vector<std::uint64_t> have;
    const od::Entry* si0 = o.find(0);
    const std::uint64_t count = si0 ? value_of(si0->default_value) : 0;
    for (std::uint64_t k = 1; k <= std::min(count, kHighestSubindex); ++k) {
      const od::Entry* e = o.find(static_cast<std::uint8_t>(k));
      have.push_back(e ? value_of(e->default_value) : 0);
    }
    if (have == values) return false;
    was = fmt::format("SI0 {}", count);
    for (auto v : have) was += fmt::format(" {:#0{}x}", v, 2 + 2 * bytes);
    if (!si0 || o.code == od::ObjectCode::Var) return false;
    for (std::size_t k = 0; k < values.size(); ++k) {
      if (!set_sub(o, static_cast<std::uint8_t>(k + 1), values[k], bytes, type)) return false;
    }
    for (auto& e : o.entries) {
      if (e.subindex > values.size()) e.default_value = le_of(0, (e.bit_length + kBitsPerByte - 1) / kBitsPerByte);
    }
    o.find(0)->default_value = le_of(values.size(), (o.find(0)->bit_length + kBitsPerByte - 1) / kBitsPerByte);
    return true;
  }

  static std::string list_text(const std::vector<std::uint64_t>& values, std::size_t bytes) {
    std::string s = fmt::format("SI0 {}", values.size());
    for (auto v : values) s += fmt::format(" {:#0{}x}", v, 2 + 2 * bytes);
    return s;
  }

  // Objects a process-data SM may be described by: 1C1xh for SM x.
  std::vector<std::size_t> process_sms(od::SmType type) const {
    std::vector<std::size_t> out;
    for (std::size_t i = 0; i < d_.sync_managers.size(); ++i) {
      if (d_.sync_managers[i].type == type) out.push_back(i);
    }
    return out;
  }

  // A PDO numbered outside its direction's mapping range (a TxPdo 1700h): the
  // CoE mapping objects of a direction live in 1600h-17FFh / 1A00h-1BFFh
  // (ETG.1000.6 §5.6.7.4.7), so the twin numbers it with the first free index
  // of its range; the process-data layout is unchanged.
  void renumber_out_of_range_pdos() {
    for (bool rx : {true, false}) {
      auto& pdos = rx ? d_.rx_pdos : d_.tx_pdos;
      const std::uint16_t first = rx ? kRxMappingFirst : kTxMappingFirst;
      const std::uint16_t last = rx ? kRxMappingLast : kTxMappingLast;
      auto used = [&](std::uint16_t i) {
        for (const auto* list : {&d_.rx_pdos, &d_.tx_pdos}) {
          for (const auto& p : *list) {
            if (p.index == i) return true;
          }
        }
        return d_.dictionary.find(i) != nullptr;
      };
      bool renumbered = false;
      for (auto& p : pdos) {
        if (p.index >= first && p.index <= last) continue;
        std::uint16_t next = first;
        while (next <= last && used(next)) ++next;
        if (next > last) continue;
        ctx_.warn_at(rx ? "RxPdo" : "TxPdo", p.source_line,
                     fmt::format("{} index {:04X}h is outside {:04X}h..{:04X}h; the twin numbers it {:04X}h", rx ? "RxPdo" : "TxPdo",
                                 p.index, first, last, next));
        for (const auto* list : {&d_.rx_pdos, &d_.tx_pdos}) {
          for (auto& q : const_cast<std::vector<od::Pdo>&>(*list)) {
            std::replace(q.excludes.begin(), q.excludes.end(), p.index, next);
          }
        }
        p.index = next;
        renumbered = true;
      }
      // A modular device's PDOs are in index order (the slots' PDOs placed
      // among the device's, esi_reader_modules.cpp); a renumbered one takes
      // its place in that order, as it will when the twin's ESI is read.
      if (renumbered && d_.modular) {
        std::stable_sort(pdos.begin(), pdos.end(), [](const od::Pdo& a, const od::Pdo& b) { return a.index < b.index; });
      }
    }
  }

  // Sizes of a process-data SM that no master could use as written:
  // - DefaultSize (no MaxSize) shorter than a PDO of its direction (Inovance
  //   SV660N: SM2 DefaultSize 12, a 19-byte RxPDO): masters size SM2/SM3 from
  //   the PDOs they assign (ETG.1000.6 §5.6.7.4), so the twin's SM takes its
  //   size from the PDOs;
  // - MaxSize whose three buffers (3-buffer mode, ESC Section I §8.2) reach
  //   into the next SM (Elmo: SM2 at 1100h MaxSize 80h, SM3 at 1180h): the
  //   ESC can only hold what fits before the next SM, so that is the maximum.
  std::uint32_t assigned_bytes(std::size_t sm) const {
    std::uint32_t bits = 0;
    for (const auto* list : {&d_.rx_pdos, &d_.tx_pdos}) {
      for (const auto& p : *list) {
        if (p.sm && *p.sm == sm) bits += p.bit_length();
      }
    }
    return (bits + kBitsPerByte - 1) / kBitsPerByte;
  }

  // Text no XML 1.0 file can hold (a name given as `A&#1;B`, which pugixml
  // reads): each forbidden character becomes '?', one byte for one, with a
  // warning; the writers would otherwise write what no parser reads back.
  void repair_text(std::string& text, const char* what, const char* element, SourcePos line) const {
    auto at = find_forbidden_xml_char(text);
    if (!at) return;
    const std::string safe = xml_safe_text(text);
    ctx_.warn_at(element, line, fmt::format("{} holds the byte {:02X}h at {}, a character XML 1.0 forbids; "
                                            "the twin has '{}'", what, static_cast<std::uint8_t>(text[*at]), *at,
                                            safe));
    text = safe;
  }

  void repair_forbidden_characters() {
    auto& id = d_.identity;
    for (auto* t : {&id.vendor_name, &id.name, &id.type_name, &id.group_type, &id.group_name, &id.hardware_version,
                    &id.software_version}) {
      repair_text(*t, "an identity text", "Device", device_line_);
    }
    std::vector<std::uint16_t> indices;
    for (const auto& o : d_.dictionary.objects()) indices.push_back(o.index);
    for (std::uint16_t index : indices) {
      od::Object& o = *d_.dictionary.find(index);
      const std::string given_name = o.name;
      repair_text(o.name, "the object's name", "Object", line_of(o));
      repair_text(o.description, "the object's description", "Object", line_of(o));
      for (auto& e : o.entries) {
        const SourcePos line = e.source_line ? SourcePos{e.source_line} : line_of(o);
        if (e.name == given_name) {
          e.name = o.name;  // a VAR's entry repeats its object's name: one warning
        } else {
          repair_text(e.name, "the entry's name", "SubItem", line);
        }
        repair_text(e.unit, "the entry's unit", "SubItem", line);
        repair_text(e.description, "the entry's description", "SubItem", line);
        if (e.type == od::DataType::VisibleString) {
          std::string v(e.default_value.begin(), e.default_value.end());
          repair_text(v, "the STRING default", "DefaultString", line);
          e.default_value.assign(v.begin(), v.end());
        }
      }
    }
    for (auto* list : {&d_.rx_pdos, &d_.tx_pdos}) {
      for (auto& p : *list) {
        const char* element = list == &d_.rx_pdos ? "RxPdo" : "TxPdo";
        repair_text(p.name, "the PDO's name", element, p.source_line ? SourcePos{p.source_line} : device_line_);
        for (auto& e : p.entries) repair_text(e.name, "the entry's name", element, p.source_line ? SourcePos{p.source_line} : device_line_);
      }
    }
    for (auto& m : d_.dc_op_modes) {
      repair_text(m.name, "the DC mode's name", "OpMode", device_line_);
      repair_text(m.description, "the DC mode's description", "OpMode", device_line_);
    }
  }

  void repair_process_sm_sizes() {
    constexpr std::uint8_t kModeMask = 0x03, kModeBuffered = 0x00;
    constexpr std::uint32_t kCopies = 3;
    for (std::size_t i = 0; i < d_.sync_managers.size(); ++i) {
      auto& sm = d_.sync_managers[i];
      const bool rx = sm.type == od::SmType::Outputs;
      if (!rx && sm.type != od::SmType::Inputs) continue;
      const SourcePos line = sm_line(i);
      if (sm.max_size == 0 && sm.default_size > 0) {
        for (const auto& p : rx ? d_.rx_pdos : d_.tx_pdos) {
          const std::uint32_t bytes = (p.bit_length() + kBitsPerByte - 1) / kBitsPerByte;
          if (bytes <= sm.default_size) continue;
          ctx_.warn_at("Sm", line, fmt::format("SM{} DefaultSize {} is shorter than PDO {:04X}h ({} bytes); "
                                               "masters size the SM from the PDOs, so does the twin", i, sm.default_size,
                                               p.index, bytes));
          sm.default_size = 0;
          break;
        }
      }
      // The PDOs assigned to the SM together (issue 32: multi-axis variants
      // whose default PDOs need 12 bytes of an Sm with 6): a master sizes the
      // SM from the assigned PDOs (SII words SM length are a hint), so does
      // the real device's ESC; the twin's SM is as long as they need.
      const std::uint32_t assigned = assigned_bytes(i);
      const std::uint16_t limit = sm.max_size ? sm.max_size : sm.default_size;
      if (limit > 0 && assigned > limit && assigned <= 0xFFFF) {
        ctx_.warn_at("Sm", line, fmt::format("SM{} {} {} is shorter than the PDOs assigned to it ({} bytes); "
                                             "masters size the SM from the PDOs, so does the twin: {} {}",
                                             i, sm.max_size ? "MaxSize" : "DefaultSize", limit, assigned,
                                             sm.max_size ? "MaxSize" : "DefaultSize", assigned));
        if (sm.max_size) {
          sm.max_size = static_cast<std::uint16_t>(assigned);
        } else {
          sm.default_size = static_cast<std::uint16_t>(assigned);
        }
      }
      // A 1-byte SM holds no buffers (ESC Section II 0x0802: length 1 is a
      // watchdog trigger only); EQ2339's input SMs at 1000h/1001h stay as they are.
      constexpr std::uint16_t kWatchdogOnlyLength = 1;
      if (sm.max_size == 0 || sm.max_size == kWatchdogOnlyLength || (sm.control & kModeMask) != kModeBuffered) continue;
      std::uint32_t next = 0;
      for (const auto& o : d_.sync_managers) {
        if (o.type != od::SmType::Unused && o.start_address > sm.start_address && (next == 0 || o.start_address < next)) {
          next = o.start_address;
        }
      }
      if (next == 0 || sm.start_address + kCopies * sm.max_size <= next) continue;
      const auto fits = static_cast<std::uint16_t>((next - sm.start_address) / kCopies);
      ctx_.warn_at("Sm", line, fmt::format("SM{} MaxSize {} needs {} bytes in 3-buffer mode from {:04X}h, but the next SM "
                                           "starts at {:04X}h; the twin's MaxSize is {}", i, sm.max_size,
                                           kCopies * sm.max_size, sm.start_address, next, fits));
      sm.max_size = fits;
      if (sm.default_size > fits) sm.default_size = fits;
    }
  }

  // Fixed process data (no CoE PDO assignment or configuration: what the SII
  // assigns is all there is) on an SM whose DefaultSize is longer than its
  // PDOs (Trinamic TMC8462-BOB: SM0 and SM1 of 8 bytes for 6 and 2 bytes of
  // PDOs). ETG.2000 gives the Sm's DefaultSize as the default PDOs' length;
  // masters size SM2/SM3 from the PDOs they assign (SOEM from the SII's PDO
  // categories, TwinCAT and IgH from the ESI's), so the real ESC runs with the
  // PDOs' length whatever the SII says; the twin's SM and SII say that length.
  // Fixed: no mailbox at all, or CoE without either. A device with mailbox
  // SMs but no CoE is left as written (no file of that shape needs it; the
  // shapes tests write mailbox SMs without a Mailbox element for other rules).
  void shrink_fixed_process_sms() {
    const bool fixed = !od::has_mailbox_sm(d_) ||
                       (d_.mailbox.coe && !d_.mailbox.pdo_assign && !d_.mailbox.pdo_config);
    if (!fixed) return;
    for (std::size_t i = 0; i < d_.sync_managers.size(); ++i) {
      auto& sm = d_.sync_managers[i];
      if (sm.type != od::SmType::Outputs && sm.type != od::SmType::Inputs) continue;
      const std::uint32_t assigned = assigned_bytes(i);
      if (assigned == 0 || sm.default_size <= assigned) continue;
      ctx_.warn_at("Sm", sm_line(i),
                   fmt::format("SM{} DefaultSize {} is longer than the PDOs assigned to it ({} bytes) and the process "
                               "data is fixed (no PDO assignment or configuration); masters size the SM from the PDOs, "
                               "so does the twin: DefaultSize {}",
                               i, sm.default_size, assigned, assigned));
      sm.default_size = static_cast<std::uint16_t>(assigned);
    }
  }

  // A process-data SM whose text says one direction while its ControlByte
  // and the PDOs assigned to it say the other (SMC EX250-SEN1: SM1
  // "Outputs", ControlByte 00h, TxPdo 1A00h Sm="1"). The master writes the
  // SII's control byte into the ESC (0x0804 bits 3:2: 00 = ECAT reads, 01 =
  // ECAT writes), so the SM's direction in the device is the control byte's,
  // and the PDO category puts the inputs there: the twin's SM is of that
  // direction. A contradiction the PDOs do not settle is left to the loader.
  void repair_sm_direction() {
    constexpr std::uint8_t kModeMask = 0x03, kModeBuffered = 0x00, kDirectionMask = 0x0C, kDirectionWrite = 0x04;
    for (std::size_t i = 0; i < d_.sync_managers.size(); ++i) {
      auto& sm = d_.sync_managers[i];
      if (sm.type != od::SmType::Outputs && sm.type != od::SmType::Inputs) continue;
      if ((sm.control & kModeMask) != kModeBuffered) continue;
      const bool control_writes = (sm.control & kDirectionMask) == kDirectionWrite;
      const bool text_writes = sm.type == od::SmType::Outputs;
      if (control_writes == text_writes) continue;
      auto on_sm = [&](const std::vector<od::Pdo>& list) {
        return std::any_of(list.begin(), list.end(), [&](const od::Pdo& p) { return p.sm && *p.sm == i; });
      };
      const bool control_pdos = on_sm(control_writes ? d_.rx_pdos : d_.tx_pdos);
      const bool text_pdos = on_sm(text_writes ? d_.rx_pdos : d_.tx_pdos);
      if (!control_pdos || text_pdos) continue;
      const od::SmType taken = control_writes ? od::SmType::Outputs : od::SmType::Inputs;
      ctx_.warn_at("Sm", sm_line(i),
                   fmt::format("SM{} is called {} but its ControlByte #x{:02X} makes it {} and the {} assigned to it "
                               "say so; taken as {}",
                               i, text_writes ? "Outputs" : "Inputs", sm.control,
                               control_writes ? "written by the master" : "read by the master",
                               control_writes ? "RxPdos" : "TxPdos", control_writes ? "Outputs" : "Inputs"));
      sm.type = taken;
    }
  }

  // A mailbox SM whose DefaultSize (what a master configures, SII words
  // 18h-1Bh) reaches the next SM's start (Beckhoff CX2040 revision
  // 0x00111B82: SM0 1000h and SM1 1200h, 1024 bytes each, SM3 at 1400h; the
  // other revisions of the device give 512): the ESC areas would overlap, a
  // master's mailbox write to SM0 would run into SM1. The twin's mailbox is
  // what fits before the next SM (MaxSize likewise), as the 3-buffer repair
  // above does for process data.
  void repair_mailbox_sm_sizes() {
    for (std::size_t i = 0; i < d_.sync_managers.size(); ++i) {
      auto& sm = d_.sync_managers[i];
      if (sm.type != od::SmType::MailboxOut && sm.type != od::SmType::MailboxIn) continue;
      const std::uint32_t size = sm.default_size ? sm.default_size : sm.max_size;
      std::uint32_t next = 0;
      for (const auto& o : d_.sync_managers) {
        if (o.type != od::SmType::Unused && o.start_address > sm.start_address && (next == 0 || o.start_address < next)) {
          next = o.start_address;
        }
      }
      if (size == 0 || next == 0 || sm.start_address + size <= next) continue;
      const auto fits = static_cast<std::uint16_t>(next - sm.start_address);
      ctx_.warn_at("Sm", sm_line(i), fmt::format("SM{} ({}) of {} bytes from {:04X}h reaches the next SM at {:04X}h; the "
                                                 "twin's mailbox is {} bytes",
                                                 i, sm.type == od::SmType::MailboxOut ? "MBoxOut" : "MBoxIn", size,
                                                 sm.start_address, next, fits));
      if (sm.default_size > fits) sm.default_size = fits;
      if (sm.max_size > fits) sm.max_size = fits;
      if (sm.min_size > fits) sm.min_size = fits;
    }
  }

  SourcePos sm_line(std::size_t n) const {
    std::size_t k = 0;
    for (auto s : device_.children("Sm")) {
      if (k++ == n) return ctx_.line(s);
    }
    return device_line_;
  }

  // The module type's PDO that is placed at `index` (slot 0 first), if any.
  od::Pdo* module_type_pdo(std::uint16_t index) {
    if (!d_.modular) return nullptr;
    od::ModularDevice& m = *d_.modular;
    for (std::size_t slot = 0; slot < m.configured.size(); ++slot) {
      for (od::ModuleType& t : m.types) {
        if (t.ident != m.configured[slot]) continue;
        for (auto* list : {&t.rx_pdos, &t.tx_pdos}) {
          for (od::Pdo& q : *list) {
            if (m.pdo_at(q.index, slot) == index) return &q;
          }
        }
      }
    }
    return nullptr;
  }

  // No PDO of a direction carries Sm, but the dictionary assigns PDOs of the
  // file: the dictionary's assignment is the only one the file gives, so the
  // SII takes it (masters that read the SII and those that read 1C12h/1C13h
  // then see the same).
  // The PDOs of the modules placed in the slots (a modular device: an IO-Link
  // master's ports) likewise: a module's PDO often carries no Sm, since where
  // it goes depends on the configuration, while the device's 1C12h/1C13h give
  // the default assignment with the default modules plugged, the one its
  // firmware serves. So a placed PDO the dictionary assigns takes that Sm even
  // where the device's own PDOs carry theirs (docs/twins.md "Import policy").
  void adopt_dictionary_assignment() {
    for (bool rx : {true, false}) {
      auto& pdos = rx ? d_.rx_pdos : d_.tx_pdos;
      const bool none_has_sm =
          std::none_of(pdos.begin(), pdos.end(), [](const od::Pdo& p) { return p.sm.has_value(); });
      const bool placed_without_sm = d_.modular && std::any_of(pdos.begin(), pdos.end(), [&](const od::Pdo& p) {
        return !p.sm && d_.modular->placed_pdo(p.index);
      });
      if (pdos.empty() || (!none_has_sm && !placed_without_sm)) continue;
      for (std::size_t sm : process_sms(rx ? od::SmType::Outputs : od::SmType::Inputs)) {
        const od::Object* o = d_.dictionary.find(static_cast<std::uint16_t>(kSmAssignFirst + sm));
        if (!o || !o->find(0)) continue;
        const auto count = std::min<std::uint64_t>(value_of(o->find(0)->default_value), kHighestSubindex);
        for (std::uint64_t k = 1; k <= count; ++k) {
          const od::Entry* e = o->find(static_cast<std::uint8_t>(k));
          if (!e) continue;
          const auto index = static_cast<std::uint16_t>(value_of(e->default_value));
          for (auto& p : pdos) {
            if (p.index == index && !p.sm && (none_has_sm || d_.modular->placed_pdo(p.index))) {
              p.sm = static_cast<std::uint8_t>(sm);
              // The device file and the ESI describe a placed PDO by its
              // module type: the type's PDO says the Sm, so the twin loaded
              // from them assigns it as the import does.
              if (od::Pdo* t = module_type_pdo(p.index); t && !t->sm) t->sm = p.sm;
              ctx_.warn_at(rx ? "RxPdo" : "TxPdo", p.source_line,
                           fmt::format("PDO {:04X}h has no Sm; assigned to SM{} as {:04X}h:{:02X} assigns it", p.index,
                                       sm, o->index, k));
            }
          }
        }
      }
      // Another placed copy of a module PDO that took an Sm above, one the
      // dictionary does not assign (its 1C1xh entry missing or unreadable):
      // the ESI and device file describe it by the same module type PDO,
      // which now says the Sm, so it is assigned there on every reload; the
      // twin assigns it now, and 1C1xh's default is compared with that.
      if (!d_.modular) continue;
      for (auto& p : pdos) {
        if (p.sm || !d_.modular->placed_pdo(p.index)) continue;
        const od::Pdo* t = module_type_pdo(p.index);
        if (!t || !t->sm) continue;
        p.sm = t->sm;
        ctx_.warn_at(rx ? "RxPdo" : "TxPdo", p.source_line,
                     fmt::format("PDO {:04X}h has no Sm; assigned to SM{} as its module's PDO {:04X}h is", p.index,
                                 *p.sm, t->index));
      }
    }
  }

  // A PDO entry whose object the dictionary lacks (devices without CoE, or
  // files that list only part of it): the twin gets a process-data object of
  // the entry's size so the data has a home; over SDO it reads as the entry.
  // Entries of one index across all PDOs make one object (a VAR for a lone
  // subindex 0, else a RECORD).
  struct Missing {
    const od::Pdo* pdo;
    const od::PdoEntry* entry;
    bool rx;
  };

  static bool derived_object(std::uint16_t index) {
    constexpr std::uint16_t kSmAssignLast = 0x1C2F, kSyncOutputs = 0x1C32, kSyncInputs = 0x1C33;
    return index == kIdentityObject || index == kSmCommType || (index >= kSmAssignFirst && index <= kSmAssignLast) ||
           (index >= kRxMappingFirst && index <= kRxMappingLast) || (index >= kTxMappingFirst && index <= kTxMappingLast) ||
           index == kSyncOutputs || index == kSyncInputs;
  }

  void create_missing_pdo_objects() {
    std::map<std::uint16_t, std::vector<Missing>> missing;
    for (bool rx : {true, false}) {
      for (const auto& p : rx ? d_.rx_pdos : d_.tx_pdos) {
        for (const auto& pe : p.entries) {
          if (pe.index == 0 || pe.bit_length == 0) continue;  // a gap, or a length already warned about
          od::Object* o = d_.dictionary.find(pe.index);
          od::Entry* e = o ? o->find(pe.subindex) : nullptr;
          const std::uint16_t map_bit = rx ? od::Access::kRxPdoMappable : od::Access::kTxPdoMappable;
          // Beckhoff terminals map status entries of the communication area
          // (1C32h:20 sync error, 1800h:07/09 TxPDO state and toggle, 1D09h:xx):
          // an existing entry is marked mappable like any other; a missing one
          // is created unless the device-file loader derives that object from
          // the SII (1018h, 1C00h, 1C1xh, 16xxh/1Axxh, 1C32h/1C33h).
          if (!e && derived_object(pe.index)) continue;
          // A PDO mapping object's entry is never process data (the MARCH
          // boards' 1A00h, data and mapping at one index: a known limit).
          const bool mapping_object = (pe.index >= kRxMappingFirst && pe.index <= kRxMappingLast) ||
                                      (pe.index >= kTxMappingFirst && pe.index <= kTxMappingLast);
          if (mapping_object) continue;
          if (e && e->bit_length > pe.bit_length && !od::is_string(e->type)) {
            // Alternative PDOs of two lengths (EJ2521: 1601h maps the UDINT
            // 7000h:12 as 16 bits, 1602h as 32): the object has one size, the
            // shorter PDO carries its low bits, as the device's process data does.
            warn(*o, fmt::format("{:04X}h:{:02X} ({} bits) is mapped by PDO {:04X}h with {} bits; the PDO carries its low "
                                 "{} bits",
                                 pe.index, pe.subindex, e->bit_length, p.index, pe.bit_length, pe.bit_length));
          }
          if (e) {
            if (!(e->access.bits & map_bit) && e->bit_length >= pe.bit_length) {
              e->access.bits |= map_bit;
              warn(*o, fmt::format("{:04X}h:{:02X} is mapped by PDO {:04X}h but not marked {}-mappable; marked",
                                   pe.index, pe.subindex, p.index, rx ? "RxPDO" : "TxPDO"));
            }
            continue;
          }
          missing[pe.index].push_back({&p, &pe, rx});
        }
      }
    }
    for (auto& [index, list] : missing) create_object(index, list);
  }

  void create_object(std::uint16_t index, const std::vector<Missing>& list) {
    const od::Object* existing = d_.dictionary.find(index);
    const bool record = existing ? existing->code != od::ObjectCode::Var
                                 : std::any_of(list.begin(), list.end(), [](const Missing& m) { return m.entry->subindex != 0; });
    const Missing& first = list.front();
    const char* element = first.rx ? "RxPdo" : "TxPdo";
    if (existing && !record) {
      warn(*existing, fmt::format("PDO {:04X}h maps {:04X}h:{:02X}, which this VAR object does not have; not repaired",
                                  first.pdo->index, index, first.entry->subindex));
      return;
    }
    od::Object obj = existing ? *existing : od::Object{};
    if (!existing) {
      obj.index = index;
      obj.name = record ? fmt::format("Process data {:04X}h", index) : first.entry->name;
      if (obj.name.empty()) obj.name = fmt::format("Process data {:04X}h", index);
      obj.source_line = first.pdo->source_line;
      obj.code = record ? od::ObjectCode::Record : od::ObjectCode::Var;
      obj.type = od::DataType::Record;
    }
    std::string added;
    for (const Missing& first_seen : list) {
      if (obj.find(first_seen.entry->subindex)) continue;  // two PDOs map the same entry (the longest made it)
      // ER1258: 1D09h:B0 (ESC register 09B0h, the 64-bit Latch0 time) mapped
      // as 32 bits by 1A11h and as 64 by 1A12h: the object takes the longest
      // length, the shorter PDO carries its low bits.
      const Missing* longest = &first_seen;
      for (const Missing& other : list) {
        if (other.entry->subindex == first_seen.entry->subindex && other.entry->bit_length > longest->entry->bit_length) {
          longest = &other;
        }
      }
      const Missing& m = *longest;
      const od::PdoEntry& pe = *m.entry;
      auto type = type_for_bits(pe.type, pe.bit_length);
      if (!type) {
        ctx_.warn_at(element, m.pdo->source_line,
                     fmt::format("entry {:04X}:{:02X} of {} bits has no object and no type of that size; not repaired",
                                 pe.index, pe.subindex, pe.bit_length));
        return;
      }
      od::Entry ne;
      ne.subindex = pe.subindex;
      ne.name = pe.name.empty() ? fmt::format("SubIndex {:03}", pe.subindex) : pe.name;
      ne.type = *type;
      ne.bit_length = pe.bit_length;
      const std::uint16_t map_bit = m.rx ? od::Access::kRxPdoMappable : od::Access::kTxPdoMappable;
      ne.access.bits = static_cast<std::uint16_t>((m.rx ? od::Access::kRw : od::Access::kRo) | map_bit);
      ne.default_value = le_of(0, (pe.bit_length + kBitsPerByte - 1) / kBitsPerByte);
      ne.source_line = m.pdo->source_line;
      auto at = std::lower_bound(obj.entries.begin(), obj.entries.end(), ne.subindex,
                                 [](const od::Entry& x, std::uint8_t sub) { return x.subindex < sub; });
      obj.entries.insert(at, std::move(ne));
      added += fmt::format("{}{:02X} ({} bits)", added.empty() ? "" : ", ", pe.subindex, pe.bit_length);
    }
    if (!obj.type_name.empty() && !existing) obj.type_name.clear();
    if (record && obj.entries.front().subindex != 0) {
      od::Entry si0;
      si0.name = "SubIndex 000";
      si0.access.bits = od::Access::kRo;
      obj.entries.insert(obj.entries.begin(), std::move(si0));
    }
    if (record) {
      od::Entry& si0 = obj.entries.front();
      // SI0 of a record reads its highest subindex (CiA 301), unless it is process data itself.
      if (!si0.access.rx_mappable() && !si0.access.tx_mappable()) si0.default_value = le_of(obj.max_subindex(), 1);
    }
    if (added.empty()) return;
    if (auto ok = d_.dictionary.put(std::move(obj)); !ok) {
      ctx_.warn_at(element, first.pdo->source_line,
                   fmt::format("object {:04X}h for PDO entries: {}; not repaired", index, ok.error()));
      return;
    }
    ctx_.warn_at(element, first.pdo->source_line,
                 fmt::format("{:04X}h has no dictionary {}; {} as process data: subindex {}", index,
                             existing ? "entry" : "object", existing ? "entries added" : "object created", added));
  }

  void repair_identity() {
    od::Object* o = d_.dictionary.find(kIdentityObject);
    if (!o) return;  // absent: the device-file loader derives it from the identity
    const auto& id = d_.identity;
    const std::uint32_t want[] = {id.vendor_id, id.product_code, id.revision, id.serial};
    const char* what[] = {"vendor id", "product code", "revision", "serial number"};
    for (std::uint8_t sub = 1; sub <= kIdentityEntries; ++sub) {
      od::Entry* e = o->find(sub);
      if (!e || e->bit_length != kIdentityBits) continue;
      if (value_of(e->default_value) == want[sub - 1] && e->default_value.size() == kIdentityBits / kBitsPerByte) continue;
      warn(*o, fmt::format("1018h:{:02X} default {} differs from the SII {} #x{:08X} (Vendor/Type); the SII's is used",
                           sub, hex_value(e->default_value), what[sub - 1], want[sub - 1]));
      e->default_value = le_of(want[sub - 1], kIdentityBits / kBitsPerByte);
    }
    // SI0 below the identity entries the object defines (Bohign's "00" next
    // to 1018h:01-04): a master reading SI0 would find no identity, and an
    // SDO upload of 1018h:01-04 would abort with 06090011h on a device that
    // answers them. SI0 = the highest of 1018h:01-04 the object has.
    od::Entry* si0 = o->find(0);
    std::uint8_t highest = 0;
    for (std::uint8_t sub = 1; sub <= kIdentityEntries; ++sub) {
      if (o->find(sub)) highest = sub;
    }
    if (si0 && !si0->default_value.empty() && value_of(si0->default_value) < highest) {
      warn(*o, fmt::format("1018h:00 default {} is below the identity entries 1018h:01-{:02X} the object defines; "
                           "SI0 is {}", hex_value(si0->default_value), highest, highest));
      si0->default_value = le_of(highest, si0->default_value.size());
    }
    // 1018h:00 naming more entries than the file gives (Inovance IS620N:
    // DefaultData 04, SubItems 0-3): the device answers SI0 = 4, so a master
    // reads 1018h:04, which is the SII's serial number (ETG.1000.6 §5.4).
    const std::uint64_t count = si0 ? value_of(si0->default_value) : 0;
    for (std::uint8_t sub = 1; sub <= kIdentityEntries && sub <= count; ++sub) {
      if (o->find(sub) || o->entries.size() < 2) continue;
      if (!set_sub(*o, sub, want[sub - 1], kIdentityBits / kBitsPerByte, od::DataType::Unsigned32)) continue;
      o->find(sub)->name = what[sub - 1];
      o->find(sub)->name[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(o->find(sub)->name[0])));
      warn(*o, fmt::format("1018h:00 default {} names subindex {:02X}, which the file does not give; the twin's is the "
                           "SII {} #x{:08X}",
                           count, sub, what[sub - 1], want[sub - 1]));
    }
  }

  void repair_sm_types() {
    od::Object* o = d_.dictionary.find(kSmCommType);
    if (!o) return;  // absent: derived by the loader from the Sm elements
    for (std::size_t i = 0; i < d_.sync_managers.size(); ++i) {
      od::Entry* e = o->find(static_cast<std::uint8_t>(i + 1));
      const std::uint8_t want = sm_type_code(d_.sync_managers[i].type);
      if (!e) {
        // A gap in the array (an ArrayInfo LBound of 2 numbers the SM types
        // from subindex 2): the device file has every subindex up to the
        // highest, so the twin's holds the Sm's type here, as a re-import of
        // the twin's ESI would repair it.
        if (o->entries.size() < 2 || !set_sub(*o, static_cast<std::uint8_t>(i + 1), want, kSmTypeBytes, od::DataType::Unsigned8)) {
          continue;
        }
        warn(*o, fmt::format("1C00h:{:02X} is missing; the twin's is the type of Sm {} ({})", i + 1, i, want));
        continue;
      }
      if (value_of(e->default_value) == want) continue;
      warn(*o, fmt::format("1C00h:{:02X} default {} differs from the type of Sm {} ({}); the Sm's is used", i + 1,
                           hex_value(e->default_value), i, want));
      e->default_value = le_of(want, (e->bit_length + kBitsPerByte - 1) / kBitsPerByte);
    }
  }

  void repair_assignments() {
    for (bool rx : {true, false}) {
      for (std::size_t sm : process_sms(rx ? od::SmType::Outputs : od::SmType::Inputs)) {
        od::Object* o = d_.dictionary.find(static_cast<std::uint16_t>(kSmAssignFirst + sm));
        if (!o) continue;  // absent: derived by the loader
        std::vector<std::uint64_t> want;
        for (const auto& p : rx ? d_.rx_pdos : d_.tx_pdos) {
          if (p.sm && *p.sm == sm) want.push_back(p.index);
        }
        std::string was;
        const bool differs = [&] {
          od::Object copy = *o;
          return rewrite_list(copy, want, kAssignBytes, od::DataType::Unsigned16, was) || !was.empty();
        }();
        if (!differs) continue;
        if (!rewrite_list(*o, want, kAssignBytes, od::DataType::Unsigned16, was)) {
          warn(*o, fmt::format("{:04X}h default ({}) differs from the PDOs with Sm=\"{}\" ({}); not repairable",
                               o->index, was, sm, list_text(want, kAssignBytes)));
          continue;
        }
        warn(*o, fmt::format("{:04X}h default ({}) differs from the PDOs with Sm=\"{}\" ({}); the SII's is used",
                             o->index, was, sm, list_text(want, kAssignBytes)));
      }
    }
  }

  // ConfigData word 0 with PDI type 0 ("interface deactivated", Section II
  // 0x0140) next to mailbox SMs: the file contradicts itself, since only a µC
  // behind a PDI answers a mailbox. The real device answers (it is sold with
  // that mailbox), so the twin runs its firmware (od::runs_firmware) and its
  // SII keeps word 0 as the file gives it.
  void warn_pdi_type_with_mailbox() {
    if ((d_.esc.pdi_control & od::kPdiTypeMask) != 0 || !od::has_mailbox_sm(d_)) return;
    const pugi::xml_node n = device_.child("Eeprom").child("ConfigData");
    ctx_.warn_at("ConfigData", n ? ctx_.line(n) : device_line_,
                 fmt::format("PDI type 00h (PDI deactivated, word 0 #x{:04X}) in a device with mailbox SMs; "
                             "the twin runs its firmware as the mailbox needs, the SII keeps word 0",
                             d_.esc.pdi_control));
  }

  // ESI files of the 1.0-1.2 era give Eeprom/ByteSize 128 (1 Kbit): the
  // 64-word fixed area alone, no room for a category (ETG.2010 §2). A master
  // reads the General, SyncM and PDO categories, so the twin's EEPROM is the
  // smallest power of two from 256 bytes that holds them all. Run last: the
  // SII follows every other repair.
  void repair_eeprom_size() {
    constexpr std::size_t kSmallest = sii::kFixedAreaBytes + sii::kBytesPerSizeUnit;
    constexpr std::size_t kLargest = 0x8000;  // 32 KiB: the uint16 ByteSize the model keeps
    const std::size_t was = d_.esc.eeprom_bytes;
    if (was >= kSmallest) return;
    std::size_t size = kSmallest;
    for (; size < kLargest; size *= 2) {
      d_.esc.eeprom_bytes = static_cast<std::uint16_t>(size);
      auto sii = write_sii_detailed(d_);
      if (sii && sii->detail == SiiDetail::Full) break;
    }
    d_.esc.eeprom_bytes = static_cast<std::uint16_t>(size);
    const pugi::xml_node n = device_.child("Eeprom").child("ByteSize");
    ctx_.warn_at("ByteSize", n ? ctx_.line(n) : device_line_,
                 fmt::format("{} bytes hold the SII's fixed area only, no category; the twin's EEPROM is {} bytes",
                             was, size));
  }

  void repair_mappings() {
    for (bool rx : {true, false}) {
      for (const auto& p : rx ? d_.rx_pdos : d_.tx_pdos) {
        const bool in_range = rx ? (p.index >= kRxMappingFirst && p.index <= kRxMappingLast)
                                 : (p.index >= kTxMappingFirst && p.index <= kTxMappingLast);
        od::Object* o = in_range ? d_.dictionary.find(p.index) : nullptr;
        if (!o) continue;  // absent: derived by the loader from the PDO
        std::vector<std::uint64_t> want;
        for (const auto& pe : p.entries) {
          want.push_back(std::uint64_t{pe.index} << kMappingIndexShift | std::uint64_t{pe.subindex} << kMappingSubShift |
                         pe.bit_length);
        }
        std::string was;
        od::Object copy = *o;
        if (!rewrite_list(copy, want, kMappingBytes, od::DataType::Unsigned32, was) && was.empty()) continue;
        if (!rewrite_list(*o, want, kMappingBytes, od::DataType::Unsigned32, was)) {
          warn(*o, fmt::format("{:04X}h default ({}) differs from the {} entries ({}); not repairable", o->index, was,
                               rx ? "RxPdo" : "TxPdo", list_text(want, kMappingBytes)));
          continue;
        }
        warn(*o, fmt::format("{:04X}h default ({}) differs from the {} entries ({}); the SII's is used", o->index, was,
                             rx ? "RxPdo" : "TxPdo", list_text(want, kMappingBytes)));
      }
    }
  }

  const EsiContext& ctx_;
  od::DeviceDescription& d_;
  pugi::xml_node device_;
  SourcePos device_line_;
};

}  // namespace

void repair_for_twin(const pugi::xml_node& device, const EsiContext& ctx, od::DeviceDescription& d) {
  Repairer(device, ctx, d).run();
}

}  // namespace ecat::esi
