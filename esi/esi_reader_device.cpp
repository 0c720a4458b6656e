// One ESI Device element (ETG.2000 DeviceType) into the model: identity,
// Profile (dictionary via esi_reader_dictionary.cpp), Fmmu, Sm, RxPdo/TxPdo,
// Mailbox, Dc/OpMode and Eeprom. Elements the model cannot hold give warnings.
#include <algorithm>
#include <limits>

#include <fmt/format.h>

#include "esi/device_values.hpp"
#include "esi/esi_reader_axes.hpp"
#include "esi/esi_reader_context.hpp"
#include "esi/esi_writer_names.hpp"

namespace ecat::esi {
namespace {

constexpr std::uint32_t kCia402ProfileNo = 402;
constexpr int kProfileShift = 16;
constexpr std::size_t kConfigWords = 5;  // SII words 0..4 that the model keeps
constexpr std::uint16_t kModesObject = 0x6502;
constexpr std::uint16_t kDeviceTypeObject = 0x1000;

std::optional<std::uint32_t> u32_of(std::string_view text) {
  auto v = esi_number(text);
  if (!v || *v < 0 || *v > std::numeric_limits<std::uint32_t>::max()) return std::nullopt;
  return static_cast<std::uint32_t>(*v);
}

od::SmType sm_type(std::string_view text, bool& known) {
  known = true;
  if (text == "MBoxOut") return od::SmType::MailboxOut;
  if (text == "MBoxIn") return od::SmType::MailboxIn;
  if (text == "Outputs") return od::SmType::Outputs;
  if (text == "Inputs") return od::SmType::Inputs;
  known = text.empty();
  return od::SmType::Unused;
}

od::FmmuUsage fmmu_usage(std::string_view text, bool& known) {
  known = true;
  if (text == "Outputs") return od::FmmuUsage::Outputs;
  if (text == "Inputs") return od::FmmuUsage::Inputs;
  if (text == "MBoxState") return od::FmmuUsage::MailboxState;
  known = text.empty();
  return od::FmmuUsage::Unused;
}

// SM control byte (ESC Section II 0x0804): bits 1:0 operation mode (10b
// mailbox, 00b buffered), bits 3:2 direction (01b written by the master).
constexpr std::uint8_t kSmModeMask = 0x03, kSmModeMailbox = 0x02, kSmModeBuffered = 0x00;
constexpr std::uint8_t kSmDirectionMask = 0x0C, kSmDirectionWrite = 0x04;

od::SmType sm_type_from_control(std::uint8_t control) {
  const bool write = (control & kSmDirectionMask) == kSmDirectionWrite;
  switch (control & kSmModeMask) {
    case kSmModeMailbox: return write ? od::SmType::MailboxOut : od::SmType::MailboxIn;
    case kSmModeBuffered: return write ? od::SmType::Outputs : od::SmType::Inputs;
    default: return od::SmType::Unused;
  }
}

const char* sm_type_word(od::SmType t) {
  switch (t) {
    case od::SmType::MailboxOut: return "MBoxOut";
    case od::SmType::MailboxIn: return "MBoxIn";
    case od::SmType::Outputs: return "Outputs";
    case od::SmType::Inputs: return "Inputs";
    case od::SmType::Unused: break;
  }
  return "unused";
}

od::FmmuUsage fmmu_by_position(std::size_t n) {
  constexpr od::FmmuUsage kOrder[] = {od::FmmuUsage::Outputs, od::FmmuUsage::Inputs, od::FmmuUsage::MailboxState};
  return n < std::size(kOrder) ? kOrder[n] : od::FmmuUsage::Unused;
}

const char* fmmu_word(od::FmmuUsage u) {
  switch (u) {
    case od::FmmuUsage::Outputs: return "Outputs";
    case od::FmmuUsage::Inputs: return "Inputs";
    case od::FmmuUsage::MailboxState: return "MBoxState";
    case od::FmmuUsage::Unused: break;
  }
  return "unused";
}

class DeviceReader {
 public:
  DeviceReader(const EsiContext& ctx, od::DeviceDescription& d) : ctx_(ctx), d_(d) {}

  Expected<void, LoadError> read(const pugi::xml_node& info, const pugi::xml_node& dev) {
    read_identity(info, dev);
    for (auto child : dev.children()) {
      const std::string_view n = child.name();
      if (child.type() != pugi::node_element || n == "Type" || n == "Name" || n == "GroupType") {
        continue;
      }
      if (n == "Profile") {
        read_profile(child);
      } else if (n == "Fmmu") {
        bool known = false;
        d_.fmmus.push_back(fmmu_usage(child.child_value(), known));
        if (!known) {
          // By position, the order ETG.2000 files and the SII FMMU category use:
          // outputs, inputs, mailbox state.
          d_.fmmus.back() = fmmu_by_position(d_.fmmus.size() - 1);
          ctx_.warn(child, fmt::format("unknown FMMU use '{}'; taken as {} by its position", child.child_value(),
                                       fmmu_word(d_.fmmus.back())));
        }
      } else if (n == "Sm") {
        read_sm(child);
      } else if (n == "RxPdo" || n == "TxPdo") {
        if (auto ok = read_pdo(child, n == "RxPdo"); !ok) return ok;
      } else if (n == "Mailbox") {
        read_mailbox(child);
      } else if (n == "Dc") {
        read_dc(child);
      } else if (n == "Eeprom") {
        read_eeprom(child);
      } else if (n == "Slots") {
        slots_ = child;
      } else {
        ctx_.ignored(child);
      }
    }
    finish();
    if (slots_) {
      const EsiPdoReader module_pdo = [this](const pugi::xml_node& pdo, bool rx, od::DeviceDescription& into) {
        return DeviceReader(ctx_, into).read_pdo(pdo, rx);
      };
      if (auto ok = read_esi_modules(info, slots_, ctx_, module_pdo, d_); !ok) return ok;
    }
    repair_for_twin(dev, ctx_, d_);
    if (auto why = recover_axes(d_)) {
      const pugi::xml_node dict = dev.child("Profile").child("Dictionary");
      ctx_.warn_at("Dictionary", ctx_.line(dict ? dict : dev), std::move(*why));
    }
    return {};
  }

 private:
  void read_identity(const pugi::xml_node& info, const pugi::xml_node& dev) {
    auto& id = d_.identity;
    auto vendor = info.child("Vendor");
    id.vendor_id = u32_of(vendor.child_value("Id")).value_or(0);
    id.vendor_name = esi_name(vendor);
    auto type = dev.child("Type");
    id.product_code = u32_of(type.attribute("ProductCode").value()).value_or(0);
    id.revision = u32_of(type.attribute("RevisionNo").value()).value_or(0);
    id.serial = u32_of(type.attribute("SerialNo").value()).value_or(0);
    id.type_name = type.child_value();
    id.name = esi_name(dev);
    if (id.name.empty() && !id.type_name.empty()) {
      // ETG.2000 requires Device/Name; the ESI written from the twin names it
      // by its Type (esi_writer.cpp), so the twin does from the start (found
      // by fuzz_twin_judge: else 1008h appeared only after a second import).
      id.name = id.type_name;
      ctx_.warn(dev, fmt::format("the device has no Name; it is named by its Type '{}'", id.type_name));
    }
    id.group_type = dev.child_value("GroupType");
    d_.esc.no_lrw = esi_bool(type.attribute("UseLrdLwr"));
    // Device@Physics (ETG.2000 PhysicsType [Y,K,H, ]{0,4}): the ports; kept
    // when it names a used port 0, else the two MII ports of the default.
    const std::string physics = dev.attribute("Physics").value();
    if (!physics.empty() && physics.size() <= 4 && physics.find_first_not_of("YKH ") == std::string::npos &&
        physics[0] != ' ') {
      d_.esc.physics = physics;
    }
    for (auto g : info.child("Descriptions").child("Groups").children("Group")) {
      if (id.group_type == g.child_value("Type")) id.group_name = esi_name(g);
    }
  }

  void read_profile(const pugi::xml_node& p) {
    if (profile_seen_) {
      ctx_.warn(p, "only the first Profile is read; this one is ignored");
      return;
    }
    profile_seen_ = true;
    profile_no_ = esi_number(p.child_value("ProfileNo")).value_or(0);
    add_info_ = esi_number(p.child_value("AddInfo")).value_or(0);
    for (auto c : p.children()) {
      const std::string_view n = c.name();
      if (n == "Dictionary") {
        read_esi_dictionary(c, ctx_, d_.dictionary);
      } else if (n != "ProfileNo" && n != "AddInfo") {
        ctx_.ignored(c);
      }
    }
  }

  void read_sm(const pugi::xml_node& s) {
    od::SyncManagerConfig sm;
    bool known = false;
    sm.type = sm_type(s.child_value(), known);
    auto u16 = [&](const char* a) {
      return ranged<std::uint16_t>(ctx_, s, a, s.attribute(a).value(), 0);
    };
    sm.start_address = u16("StartAddress");
    sm.default_size = u16("DefaultSize");
    sm.min_size = u16("MinSize");
    sm.max_size = u16("MaxSize");
    sm.control = ranged<std::uint8_t>(ctx_, s, "ControlByte", s.attribute("ControlByte").value(), 0);
    sm.enable = (ranged<std::uint8_t>(ctx_, s, "Enable", s.attribute("Enable").value(), 1) & 1) != 0;
    // An Sm without text but with a ControlByte (IgH's `ethercat xml` writes
    // none, its SII reading has the type only in the SYNCM category): the
    // control byte says what the SM is, as for a text that is not one of
    // the four words.
    const bool untyped = *s.child_value() == '\0' && s.attribute("ControlByte");
    if (!known || untyped) {
      // The SII SYNCM type a master reads follows the control byte (ESC Section II
      // 0x0804: bits 1:0 mode, bits 3:2 direction) when the text is not one of
      // the four ETG.2000 words (e.g. "OrbitaIn").
      sm.type = sm_type_from_control(sm.control);
      ctx_.warn(s, untyped ? fmt::format("no SM use given; taken as {} from ControlByte #x{:02X}",
                                         sm_type_word(sm.type), sm.control)
                           : fmt::format("unknown SM use '{}'; taken as {} from ControlByte #x{:02X}",
                                         s.child_value(), sm_type_word(sm.type), sm.control));
    }
    d_.sync_managers.push_back(sm);
  }

  Expected<void, LoadError> read_pdo(const pugi::xml_node& n, bool rx) {
    od::Pdo p;
    auto index = u32_of(n.child_value("Index"));
    if (!n.child("Index") && n.attribute("Ref")) {
      // ESI files of the 1.0-1.2 era (Beckhoff "EtherCAT Terminals.xml")
      // name PDO templates that TwinCAT holds, not the file: the PDO's index
      // and entries are not in the file.
      return ecat::fail(ctx_.error(n, fmt::format("{} Ref=\"{}\": a PDO template this file does not contain "
                                                  "(pre-ETG.2000 reference); its index and entries are unknown",
                                                  rx ? "RxPdo" : "TxPdo", n.attribute("Ref").value())));
    }
    if (!index || *index > 0xFFFF) {
      return ecat::fail(ctx_.error(n, fmt::format("PDO index '{}' is not a 16-bit number",
                                                  n.child_value("Index"))));
    }
    p.index = static_cast<std::uint16_t>(*index);
    p.name = esi_name(n);
    if (p.name.empty()) {
      ctx_.warn(n, fmt::format("PDO {:04X}h has no Name; its mapping object is named 'PDO {:04X}h'", p.index,
                               p.index));
    }
    p.fixed = esi_bool(n.attribute("Fixed"));
    p.mandatory = esi_bool(n.attribute("Mandatory"));
    if (auto sm = n.attribute("Sm")) p.sm = ranged<std::uint8_t>(ctx_, n, "Sm", sm.value(), 0);
    p.source_line = ctx_.line(n);
    for (auto x : n.children("Exclude")) {
      p.excludes.push_back(ranged<std::uint16_t>(ctx_, x, "Exclude", x.child_value(), 0));
    }
    for (auto e : n.children("Entry")) {
      od::PdoEntry pe;
      pe.index = entry_index(e);
      pe.subindex = ranged<std::uint8_t>(ctx_, e, "SubIndex", e.child_value("SubIndex"), 0);
      pe.bit_length = ranged<std::uint8_t>(ctx_, e, "BitLen", e.child_value("BitLen"), 0);
      if (pe.bit_length == 0) {
        // A placeholder of no bits (Index 0, SubIndex 0, BitLen 0 in a PDO of a
        // device without process data): it maps nothing, in the SII as in CoE.
        ctx_.warn(e, fmt::format("PDO {:04X}h entry {:04X}h:{:02X} has BitLen 0: it maps nothing; dropped", p.index,
                                 pe.index, pe.subindex));
        continue;
      }
      pe.name = esi_name(e);
      auto dt = e.child("DataType");
      if (auto t = parse_esi_type_name(dt.child_value()); t && dt) {
        pe.type = t->type;
      } else if (pe.index != 0) {
        if (dt) ctx_.warn(dt, fmt::format("unknown PDO entry type '{}'", dt.child_value()));
        untyped_.push_back({rx, (rx ? d_.rx_pdos : d_.tx_pdos).size(), p.entries.size()});
      }
      p.entries.push_back(pe);
    }
    (rx ? d_.rx_pdos : d_.tx_pdos).push_back(std::move(p));
    return {};
  }

  // A PDO entry's Index. ETG.2000 HexDecValue: without "#x" it is decimal,
  // so <Index>7000</Index> is 1B58h. Issue 32's policy (docs/twins.md): the
  // decimal reading stands unless it names no object of the dictionary and
  // the same digits read as hex name one (the firmware serves that object,
  // and its CoE mapping objects say so), or the decimal reading lies in the
  // communication area 1000h-1FFFh, which holds no process data, and the
  // hex reading does not: then the hex reading, with a warning at the line.
  std::uint16_t entry_index(const pugi::xml_node& e) const {
    const std::string text = e.child_value("Index");
    const auto dec = ranged<std::uint16_t>(ctx_, e, "Index", text, 0);
    const bool digits = text.size() >= 2 && std::all_of(text.begin(), text.end(), [](char c) {
      return c >= '0' && c <= '9';
    });
    if (!digits || text.size() > 4 || dec == 0) return dec;
    const auto hex = static_cast<std::uint16_t>(std::stoul(text, nullptr, 16));
    if (d_.dictionary.find(dec)) return dec;
    constexpr std::uint16_t kCommFirst = 0x1000, kCommLast = 0x1FFF;
    const bool comm = dec >= kCommFirst && dec <= kCommLast;
    const bool hex_known = d_.dictionary.find(hex) != nullptr;
    const bool hex_process = hex > kCommLast;
    if (hex_known || (comm && hex_process)) {
      ctx_.warn(e.child("Index"),
                fmt::format("Index '{}' is decimal by ETG.2000 ({:04X}h), {}; read as #x{}, {}", text, dec,
                            comm ? "in the communication area, which holds no process data" : "an object the dictionary lacks",
                            text, hex_known ? "the object the dictionary has" : "a process-data index"));
      return hex;
    }
    return dec;
  }

  void read_mailbox(const pugi::xml_node& m) {
    mailbox_seen_ = true;
    auto& mb = d_.mailbox;
    mb = od::MailboxProtocols{};
    mb.coe = false;
    for (auto c : m.children()) {
      const std::string_view n = c.name();
      if (n == "CoE") {
        mb.coe = true;
        mb.sdo_info = esi_bool(c.attribute("SdoInfo"));
        mb.pdo_assign = esi_bool(c.attribute("PdoAssign"));
        mb.pdo_config = esi_bool(c.attribute("PdoConfig"));
        mb.pdo_upload = esi_bool(c.attribute("PdoUpload"));
        mb.complete_access = esi_bool(c.attribute("CompleteAccess"));
        mb.segmented_sdo = esi_bool(c.attribute("SegmentedSdo"));
        for (auto x : c.children()) ctx_.ignored(x);  // InitCmd, Object
      } else if (n == "FoE") {
        mb.foe = true;
      } else if (n == "EoE") {
        mb.eoe = true;
        for (auto x : c.children()) ctx_.ignored(x);
      } else if (n == "SoE") {
        mb.soe = true;
        for (auto x : c.children()) ctx_.ignored(x);
      } else {
        ctx_.ignored(c);  // AoE, VoE, VendorSpecific
      }
    }
  }

  void read_dc(const pugi::xml_node& dc) {
    for (auto op : dc.children()) {
      if (std::string_view(op.name()) != "OpMode") {
        ctx_.ignored(op);
        continue;
      }
      od::DcOpMode m;
      m.cycle_time_sync1_factor = 0;
      for (auto c : op.children()) {
        const std::string_view n = c.name();
        const std::string_view text = c.child_value();
        if (n == "Name") {
          m.name = c.child_value();
        } else if (n == "Desc") {
          m.description = c.child_value();
        } else if (n == "AssignActivate") {
          m.assign_activate = ranged<std::uint16_t>(ctx_, c, n, text, 0);
        } else if (n == "CycleTimeSync0" || n == "CycleTimeSync1") {
          auto& factor = n == "CycleTimeSync0" ? m.cycle_time_sync0_factor : m.cycle_time_sync1_factor;
          factor = ranged<std::int32_t>(ctx_, c, "Factor", c.attribute("Factor").value(), 1);
          if (ranged<std::int32_t>(ctx_, c, n, text, 0) != 0) {
            ctx_.warn(c, "a fixed cycle time is not modelled; only Factor is kept");
          }
        } else if (n == "ShiftTimeSync0") {
          m.shift_time_sync0 = ranged<std::int32_t>(ctx_, c, n, text, 0);
        } else if (n == "ShiftTimeSync1") {
          m.shift_time_sync1 = ranged<std::int32_t>(ctx_, c, n, text, 0);
        } else {
          ctx_.ignored(c);  // Sm, VendorSpecific
        }
      }
      d_.dc_op_modes.push_back(std::move(m));
    }
  }

  void read_eeprom(const pugi::xml_node& e) {
    for (auto c : e.children()) {
      const std::string_view n = c.name();
      if (n == "ByteSize") {
        d_.esc.eeprom_bytes = ranged<std::uint16_t>(ctx_, c, n, c.child_value(), d_.esc.eeprom_bytes);
      } else if (n == "ConfigData") {
        auto bytes = parse_hex_binary(c.child_value());
        if (!bytes) {
          ctx_.warn(c, "not hexBinary; ignored");
          continue;
        }
        for (std::size_t i = kConfigWords * 2; i < bytes->size(); ++i) {
          if ((*bytes)[i] != 0) {
            ctx_.warn(c, "bytes after word 4 (reserved words 5-6) are not modelled; written as 0");
            break;
          }
        }
        bytes->resize(kConfigWords * 2, 0);
        std::uint16_t w[kConfigWords];
        for (std::size_t i = 0; i < kConfigWords; ++i) {
          w[i] = static_cast<std::uint16_t>((*bytes)[2 * i] | ((*bytes)[2 * i + 1] << 8));
        }
        d_.esc.pdi_control = w[0];
        d_.esc.pdi_configuration = w[1];
        d_.esc.sync_impulse_length = w[2];
        d_.esc.pdi_configuration2 = w[3];
        d_.esc.configured_station_alias = w[4];
      } else if (n == "BootStrap") {
        d_.bootstrap_supported = true;
        bootstrap_node_ = c;
      } else {
        ctx_.ignored(c);  // Data, Category, VendorSpecific
      }
    }
  }

  // Values that depend on several elements.
  void finish() {
    auto& id = d_.identity;
    if (const auto* e = d_.dictionary.find(kDeviceTypeObject, 0); e && e->default_value.size() == 4) {
      id.device_type = static_cast<std::uint32_t>(e->default_value[0] | (e->default_value[1] << 8) |
                                                  (e->default_value[2] << 16) |
                                                  (static_cast<std::uint32_t>(e->default_value[3]) << 24));
    } else {
      id.device_type = static_cast<std::uint32_t>(profile_no_ | (add_info_ << kProfileShift));
    }
    auto text_of = [&](std::uint16_t index) {
      const auto* e = d_.dictionary.find(index, 0);
      return e ? std::string(e->default_value.begin(), e->default_value.end()) : std::string{};
    };
    id.hardware_version = text_of(0x1009);
    id.software_version = text_of(0x100A);
    if (profile_no_ == kCia402ProfileNo) {
      od::DriveProfile drive;
      if (const auto* e = d_.dictionary.find(kModesObject, 0)) {
        for (std::size_t i = 0; i < e->default_value.size() && i < 4; ++i) {
          drive.supported_modes |= static_cast<std::uint32_t>(e->default_value[i]) << (8 * i);
        }
      }
      d_.drive = drive;
    }
    // PDO entries without a (known) DataType take the object's type.
    for (const auto& u : untyped_) {
      auto& e = (u.rx ? d_.rx_pdos : d_.tx_pdos)[u.pdo].entries[u.entry];
      if (const auto* oe = d_.dictionary.find(e.index, e.subindex)) e.type = oe->type;
    }
    if (!mailbox_seen_) d_.mailbox = od::MailboxProtocols{false, false, false, false, false,
                                                          false, false, false, false, false};
    if (bootstrap_node_) check_bootstrap();
  }

  // The model keeps no separate Bootstrap mailbox: it reuses SM0/SM1's layout.
  void check_bootstrap() const {
    auto bytes = parse_hex_binary(bootstrap_node_.child_value()).value_or(od::Value{});
    od::Value standard;
    for (const auto& sm : d_.sync_managers) {
      if (sm.type != od::SmType::MailboxOut && sm.type != od::SmType::MailboxIn) continue;
      for (std::uint16_t w : {sm.start_address, sm.default_size}) {
        standard.push_back(static_cast<std::uint8_t>(w));
        standard.push_back(static_cast<std::uint8_t>(w >> 8));
      }
    }
    if (bytes != standard) {
      ctx_.warn(bootstrap_node_, "a Bootstrap mailbox layout other than the standard mailbox's is "
                                 "not modelled; the standard layout is used");
    }
  }

  const EsiContext& ctx_;
  od::DeviceDescription& d_;
  bool profile_seen_ = false;
  std::int64_t profile_no_ = 0;
  std::int64_t add_info_ = 0;
  pugi::xml_node bootstrap_node_;
  pugi::xml_node slots_;
  bool mailbox_seen_ = false;
  struct Untyped {
    bool rx;
    std::size_t pdo;
    std::size_t entry;
  };
  std::vector<Untyped> untyped_;
};

}  // namespace

Expected<void, LoadError> read_esi_device(const pugi::xml_node& info, const pugi::xml_node& device,
                                          const EsiContext& ctx, od::DeviceDescription& out) {
  return DeviceReader(ctx, out).read(info, device);
}

}  // namespace ecat::esi
