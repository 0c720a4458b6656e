// Profile/Dictionary import (ETG.2000 DictionaryType): DataTypes are resolved
// to the model's basic types; a DataType with SubItems makes an ARRAY (when a
// SubItem without SubIdx refers to an ArrayInfo type, the "Elements" shape)
// or a RECORD; Object Info gives default/min/max (hexBinary little-endian,
// HexDecValue or DefaultString) and Flags the access bits.
#include <algorithm>
#include <map>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "esi/device_values.hpp"
#include "esi/esi_reader_context.hpp"
#include "esi/esi_writer_names.hpp"
#include "esi/xml_chars.hpp"

namespace ecat::esi {
namespace {

constexpr int kMaxTypeDepth = 8;  // BaseType chains longer than this are rejected
constexpr std::uint16_t kBitsPerByte = 8;
constexpr std::uint8_t kSignBit = 0x80;      // top bit of the last little-endian byte
constexpr std::uint8_t kSignFill = 0xFF;     // bytes that sign-extend a negative number
// ETG.1020 diagnosis history and its "Maximum messages" subindex.
constexpr std::uint16_t kDiagnosisHistory = 0x10F3;
constexpr std::uint8_t kDiagMaxMessagesSub = 1;

struct Basic {
  od::DataType type;
  std::uint16_t bits;
};

od::DataType record_type(std::uint16_t index) {
  if (index == 0x1018) return od::DataType::Identity;
  if ((index >= 0x1600 && index < 0x1800) || (index >= 0x1A00 && index < 0x1C00)) {
    return od::DataType::PdoMapping;
  }
  if (index == 0x1C32 || index == 0x1C33) return od::DataType::SmSynchronisation;
  if (index == 0x10F1) return od::DataType::ErrorSetting;
  return od::DataType::Record;
}

std::optional<Basic> unsigned_of_size(std::int64_t bits) {
  switch (bits) {
    case 8: return Basic{od::DataType::Unsigned8, 8};
    case 16: return Basic{od::DataType::Unsigned16, 16};
    case 32: return Basic{od::DataType::Unsigned32, 32};
    default:
      if (bits >= 1 && bits < 8) {
        return Basic{static_cast<od::DataType>(static_cast<std::uint16_t>(od::DataType::Bit1) + bits - 1),
                     static_cast<std::uint16_t>(bits)};
      }
      return std::nullopt;
  }
}

class DictionaryReader {
 public:
  DictionaryReader(const pugi::xml_node& dict, const EsiContext& ctx) : ctx_(ctx) {
    for (auto c : dict.children()) {
      const std::string_view n = c.name();
      if (n == "DataTypes") {
        for (auto t : c.children("DataType")) types_[t.child_value("Name")] = t;
      } else if (n != "Objects") {
        ctx_.ignored(c);
      }
    }
  }

  void read_object(const pugi::xml_node& obj, od::Dictionary& out) {
    auto index = esi_number(obj.child_value("Index"));
    if (!index || *index < 0 || *index > 0xFFFF) {
      ctx_.warn(obj, fmt::format("object index '{}' is not a 16-bit number; object skipped",
                                 obj.child_value("Index")));
      return;
    }
    od::Object o;
    o.index = static_cast<std::uint16_t>(*index);
    o.name = esi_name(obj);
    o.description = esi_name(obj, "Comment");
    o.source_line = ctx_.line(obj);
    const std::string type = obj.child_value("Type");
    const auto bits = esi_number(obj.child_value("BitSize")).value_or(0);
    const std::uint16_t access = read_flags(obj.child("Flags"), od::Access::kRo);
    if (auto b = basic(type, bits, 0)) {
      od::Entry e = make_entry(0, o.name, *b, access, obj);
      e.description = o.description;
      set_values(e, obj.child("Info"));
      o.code = od::ObjectCode::Var;
      o.type = b->type;
      o.entries.push_back(std::move(e));
    } else if (auto it = types_.find(type); it != types_.end() && it->second.child("SubItem")) {
      if (!read_structured(o, it->second, obj, access)) return;
    } else {
      ctx_.warn(obj, fmt::format("object {:04X}h: {} data type '{}'; object skipped", o.index,
                                 types_.count(type) ? "unsupported" : "unknown", type));
      return;
    }
    if (auto ok = out.put(std::move(o)); !ok) ctx_.warn(obj, ok.error() + "; object skipped");
  }

 private:
  // A type name as a basic (VAR-able) type: the IEC names, aliases via
  // BaseType, enums (as unsigned of their size) and BYTE arrays (octet strings).
  std::optional<Basic> basic(const std::string& name, std::int64_t bits, int depth) const {
    auto it = types_.find(name);
    if (it != types_.end() && it->second.child("SubItem")) return std::nullopt;
    if (auto t = parse_esi_type_name(name)) {
      std::uint16_t b = t->bit_length ? t->bit_length : od::fixed_bit_size(t->type);
      if (b == 0) b = static_cast<std::uint16_t>(bits);
      return Basic{t->type, b};
    }
    if (it == types_.end() || depth > kMaxTypeDepth) return std::nullopt;
    const auto& dt = it->second;
    const auto dt_bits = esi_number(dt.child_value("BitSize")).value_or(bits);
    const std::string base = dt.child_value("BaseType");
    if (dt.child("ArrayInfo")) {
      auto b = basic(base, 0, depth + 1);
      if (b && b->bits == kBitsPerByte && !dt.child("ArrayInfo").next_sibling("ArrayInfo")) {
        return Basic{od::DataType::OctetString, static_cast<std::uint16_t>(dt_bits)};
      }
      return std::nullopt;
    }
    if (!base.empty()) return basic(base, dt_bits, depth + 1);
    if (dt.child("EnumInfo")) return unsigned_of_size(dt_bits);
    return std::nullopt;
  }

  std::uint16_t read_flags(const pugi::xml_node& flags, std::uint16_t fallback) const {
    if (!flags) return fallback;
    std::uint16_t bits = fallback;
    if (auto a = flags.child("Access")) {
      auto v = parse_esi_access(a.child_value(), a.attribute("ReadRestrictions").value(),
                                a.attribute("WriteRestrictions").value());
      if (v) {
        bits = *v;
      } else {
        ctx_.warn(a, fmt::format("unknown access '{}'; taken as ro", a.child_value()));
        bits = od::Access::kRo;
      }
    } else {
      bits = static_cast<std::uint16_t>(fallback & od::Access::kRw);
    }
    if (auto m = flags.child("PdoMapping")) {
      if (auto v = parse_esi_pdo_mapping(m.child_value())) {
        bits = static_cast<std::uint16_t>(bits | *v);
      } else {
        ctx_.warn(m, fmt::format("unknown PdoMapping '{}'; ignored", m.child_value()));
      }
    }
    if (esi_number(flags.child_value("Backup")).value_or(0) != 0) bits |= od::Access::kBackup;
    if (esi_number(flags.child_value("Setting")).value_or(0) != 0) bits |= od::Access::kSetting;
    return bits;
  }

  od::Entry make_entry(std::uint8_t sub, std::string name, Basic b, std::uint16_t access,
                       const pugi::xml_node& where) const {
    od::Entry e;
    e.subindex = sub;
    e.name = std::move(name);
    e.type = b.type;
    e.bit_length = b.bits;
    e.access.bits = access;
    e.source_line = ctx_.line(where);
    return e;
  }

  bool read_structured(od::Object& o, const pugi::xml_node& dt, const pugi::xml_node& obj,
                       std::uint16_t object_access) {
    o.type_name = dt.child_value("Name");
    std::vector<pugi::xml_node> infos;
    for (auto s : obj.child("Info").children("SubItem")) infos.push_back(s);
    auto info_named = [&](const std::string& name, std::size_t position) -> pugi::xml_node {
      for (auto s : infos) {
        if (name == s.child_value("Name")) return s;
      }
      return position < infos.size() ? infos[position] : pugi::xml_node{};
    };
    bool array = false;
    bool si0_given = true;  // only a subindex 0 read without a default is repaired
    bool diag_max_given = true;  // 10F3h:01 read without a default is repaired (default_diagnosis_capacity)
    int next_sub = 0;
    for (auto si : dt.children("SubItem")) {
      const std::string stype = si.child_value("Type");
      const auto sbits = esi_number(si.child_value("BitSize")).value_or(0);
      const std::uint16_t access = read_flags(si.child("Flags"), object_access);
      auto arr = types_.find(stype);
      if (!si.child("SubIdx") && arr != types_.end() && arr->second.child("ArrayInfo")) {
        // "Elements": one entry per array element, named by the object's Info.
        auto ai = arr->second.child("ArrayInfo");
        const auto lbound = esi_number(ai.child_value("LBound")).value_or(1);
        const auto n = esi_number(ai.child_value("Elements")).value_or(0);
        auto elem = basic(arr->second.child_value("BaseType"), n > 0 ? sbits / n : 0, 0);
        if (!elem || ai.next_sibling("ArrayInfo") || lbound < 0 || lbound + n > 256) {
          ctx_.warn(obj, fmt::format("object {:04X}h: array type '{}' not modelled; object skipped",
                                     o.index, stype));
          return false;
        }
        for (std::int64_t k = 0; k < n; ++k) {
          const auto sub = static_cast<std::uint8_t>(lbound + k);
          auto info = o.entries.size() < infos.size() ? infos[o.entries.size()] : pugi::xml_node{};
          std::string name = info ? info.child_value("Name") : fmt::format("SubIndex {:03}", sub);
          od::Entry e = make_entry(sub, std::move(name), *elem, access, si);
          set_values(e, info.child("Info"));
          o.entries.push_back(std::move(e));
        }
        array = true;
        next_sub = static_cast<int>(lbound + n);
        continue;
      }
      if (stype.empty() && !si.child("Type")) {
        // A SubItem without a Type: padding in the complete-access image (its
        // BitSize), not an entry a master can address.
        ctx_.warn(si, fmt::format("object {:04X}h: sub item '{}' has no Type; taken as {} bits of padding, not an entry",
                                  o.index, si.child_value("Name"), sbits));
        if (si.child("SubIdx")) next_sub = static_cast<int>(esi_number(si.child_value("SubIdx")).value_or(next_sub)) + 1;
        continue;
      }
      auto b = basic(stype, sbits, 0);
      const auto sub = si.child("SubIdx") ? esi_number(si.child_value("SubIdx")) : next_sub;
      if (!b || !sub || *sub < 0 || *sub > 255) {
        ctx_.warn(si, fmt::format("object {:04X}h: sub item '{}' of type '{}' not modelled; object "
                                  "skipped",
                                  o.index, si.child_value("Name"), stype));
        return false;
      }
      od::Entry e = make_entry(static_cast<std::uint8_t>(*sub), si.child_value("Name"), *b, access, si);
      const pugi::xml_node info = info_named(e.name, o.entries.size()).child("Info");
      if (e.subindex == 0) si0_given = has_default(info);
      if (e.subindex == kDiagMaxMessagesSub) diag_max_given = has_default(info);
      set_values(e, info);
      o.entries.push_back(std::move(e));
      next_sub = static_cast<int>(*sub) + 1;
    }
    o.code = array ? od::ObjectCode::Array : od::ObjectCode::Record;
    o.type = array && o.entries.size() > 1 ? o.entries[1].type : record_type(o.index);
    if (!si0_given) default_highest_subindex(o, obj);
    if (!diag_max_given && o.index == kDiagnosisHistory) default_diagnosis_capacity(o, obj);
    return true;
  }

  static bool has_default(const pugi::xml_node& info) {
    return info.child("DefaultData") || info.child("DefaultValue") || info.child("DefaultString");
  }

  // Subindex 0 of a RECORD or ARRAY without a default in the file (Elmo
  // Gold's 1018h, 60FEh): a device answers its highest subindex there
  // (CiA 301 §7.4.3.1, "highest sub-index supported"; ETG.1000.6 §5.6.3.5),
  // so the twin's reads that, with a warning. Not for the objects whose
  // subindex 0 counts what is configured (16xxh/1Axxh mapped objects,
  // 1C10h-1C2Fh assigned PDOs): an empty mapping or assignment is 0, and
  // the twin repairs decide those from the SII's PDOs.
  // ETG.1020 diagnosis history 10F3h: subindex 1 "Maximum messages" is the
  // number of messages the ring holds, in subindices 6..5+n. A file that
  // declares the message subindices but gives 10F3h:01 no default (Copley's
  // XE2: 100 messages, no DefaultData anywhere in the object) would leave the
  // twin's history without a ring (coe/diagnosis_history.cpp takes its size
  // from 10F3h:01), while the device keeps the ring its layout describes: the
  // twin's 10F3h:01 reads the number of message subindices declared.
  void default_diagnosis_capacity(od::Object& o, const pugi::xml_node& obj) const {
    constexpr unsigned kFirstMessageSub = 6, kLastSub = 0xFF;
    od::Entry* max = o.find(kDiagMaxMessagesSub);
    if (!max || max->bit_length != kBitsPerByte) return;
    unsigned messages = 0;
    while (kFirstMessageSub + messages <= kLastSub && o.find(static_cast<std::uint8_t>(kFirstMessageSub + messages))) {
      ++messages;
    }
    if (messages == 0) return;
    max->default_value = {static_cast<std::uint8_t>(messages)};
    ctx_.warn(obj, fmt::format("10F3h:01 (maximum messages) has no default; the twin's diagnosis history holds the {} "
                               "messages of subindices {:02X}..{:02X} it declares (ETG.1020)",
                               messages, kFirstMessageSub, kFirstMessageSub + messages - 1));
  }

  void default_highest_subindex(od::Object& o, const pugi::xml_node& obj) const {
    constexpr std::uint16_t kRxMapFirst = 0x1600, kRxMapLast = 0x17FF, kTxMapFirst = 0x1A00, kTxMapLast = 0x1BFF;
    constexpr std::uint16_t kAssignFirst = 0x1C10, kAssignLast = 0x1C2F;
    const bool counts = (o.index >= kRxMapFirst && o.index <= kRxMapLast) ||
                        (o.index >= kTxMapFirst && o.index <= kTxMapLast) ||
                        (o.index >= kAssignFirst && o.index <= kAssignLast);
    od::Entry* si0 = o.find(0);
    const std::uint8_t highest = o.max_subindex();
    if (counts || !si0 || highest == 0 || od::is_string(si0->type)) return;
    si0->default_value = le_bytes(highest, (si0->bit_length + kBitsPerByte - 1u) / kBitsPerByte);
    ctx_.warn(obj, fmt::format("{:04X}h:00 has no default; the twin's reads {}, the highest subindex (CiA 301)",
                               o.index, highest));
  }

  // One value from Info: hexBinary Data, HexDecValue Value, or (default) a string.
  std::optional<od::Value> value_of(const od::Entry& e, const pugi::xml_node& info, const char* data,
                                    const char* value) const {
    const std::size_t size = (e.bit_length + kBitsPerByte - 1u) / kBitsPerByte;
    if (auto n = info.child(data)) {
      auto bytes = parse_hex_binary(n.child_value());
      if (!bytes) {
        ctx_.warn(n, fmt::format("'{}' is not hexBinary; ignored", n.child_value()));
        return std::nullopt;
      }
      if (!od::is_string(e.type) && bytes->size() != size) {
        // The number in fewer bytes: zero-extended, or sign-extended for a
        // signed type ("80" for an INT is -128, as the vendor tool meant).
        const bool negative = od::is_signed(e.type) && !bytes->empty() && bytes->size() < size &&
                              (bytes->back() & kSignBit) != 0;
        ctx_.warn(n, fmt::format("{} bytes for a {}-bit entry; {}", bytes->size(), e.bit_length,
                                 negative ? "sign-extended" : "resized"));
        bytes->resize(size, negative ? kSignFill : 0);
      }
      return bytes;
    }
    if (auto n = info.child(value)) {
      auto v = esi_number(n.child_value());
      if (!v) {
        ctx_.warn(n, fmt::format("'{}' is not a number; ignored", n.child_value()));
        return std::nullopt;
      }
      return le_bytes(static_cast<std::uint64_t>(*v), size);
    }
    return std::nullopt;
  }

  // A STRING default given as DefaultData bytes (issue 32, docs/twins.md
  // "Import policy"): the string ends at its first 00 byte (NUL padding, as a
  // device pads a VISIBLE_STRING to its length); bytes after it are dropped
  // with a warning. A string that still holds a control character XML 1.0
  // forbids (`0100`: 01h) is no VISIBLE_STRING (CiA 301: visible characters):
  // the entry keeps no default, with a warning, and no writer emits it.
  void string_from_bytes(od::Entry& e, const pugi::xml_node& info) const {
    const auto data = info.child("DefaultData") ? info.child("DefaultData") : info.child("DefaultValue");
    const std::string given = data.child_value();
    auto& v = e.default_value;
    const auto nul = std::find(v.begin(), v.end(), std::uint8_t{0});
    if (std::any_of(nul, v.end(), [](std::uint8_t b) { return b != 0; })) {
      ctx_.warn(data, fmt::format("STRING default {} ends at its first 00 byte; the bytes after it are dropped",
                                  given));
    }
    v.erase(nul, v.end());
    const std::string text(v.begin(), v.end());
    if (auto at = find_forbidden_xml_char(text)) {
      ctx_.warn(data, fmt::format("STRING default {} holds the byte {:02X}h, a control character no VISIBLE_STRING "
                                  "and no XML file holds; the entry keeps no default",
                                  given, static_cast<std::uint8_t>(text[*at])));
      v.clear();
    }
  }

  void set_values(od::Entry& e, const pugi::xml_node& info) const {
    if (auto s = info.child("DefaultString")) {
      const std::string_view text = s.child_value();
      for (char c : text) {
        e.default_value.push_back(static_cast<std::uint8_t>(c));
        if (e.type == od::DataType::UnicodeString) e.default_value.push_back(0);
      }
      // STRING(0) with a default "1.0" (generated files): the device answers the
      // default, so the entry is as long as its default.
      const std::size_t have = e.bit_length / kBitsPerByte;
      if (e.default_value.size() > have) {
        ctx_.warn(s, fmt::format("default '{}' is longer than the declared {} bytes; the entry is made {} bytes",
                                 text, have, e.default_value.size()));
        e.bit_length = static_cast<std::uint16_t>(e.default_value.size() * kBitsPerByte);
      }
    } else if (auto v = value_of(e, info, "DefaultData", "DefaultValue")) {
      e.default_value = std::move(*v);
      if (e.type == od::DataType::VisibleString) string_from_bytes(e, info);
    }
    if (auto v = value_of(e, info, "MinData", "MinValue")) e.min_value = std::move(*v);
    if (auto v = value_of(e, info, "MaxData", "MaxValue")) e.max_value = std::move(*v);
    if (e.has_min() && e.has_max() && compare_values(e.type, e.min_value, e.max_value) > 0) {
      // A range no value fits (e.g. MinData 80, MaxData 00 of a 16-bit entry):
      // the device cannot mean it; the twin takes no limits.
      ctx_.warn(info, "MinData above MaxData; the entry gets no limits");
      e.min_value.clear();
      e.max_value.clear();
    }
    if (e.default_value.empty()) e.default_value = zero_value(e.type, e.bit_length);
    // A default outside its own limits (Inovance IS620N 2002h: default 20,
    // MaxData 2): the device powers up with the default and answers it to an
    // upload, so the twin keeps the default and drops the limit it breaks.
    if (e.has_min() && compare_values(e.type, e.default_value, e.min_value) < 0) {
      ctx_.warn(info, "DefaultData below MinData; the device starts with its default, the entry gets no minimum");
      e.min_value.clear();
    }
    if (e.has_max() && compare_values(e.type, e.default_value, e.max_value) > 0) {
      ctx_.warn(info, "DefaultData above MaxData; the device starts with its default, the entry gets no maximum");
      e.max_value.clear();
    }
  }

  const EsiContext& ctx_;
  std::map<std::string, pugi::xml_node> types_;
};

}  // namespace

void read_esi_dictionary(const pugi::xml_node& dictionary, const EsiContext& ctx,
                         od::Dictionary& out) {
  DictionaryReader reader(dictionary, ctx);
  for (auto obj : dictionary.child("Objects").children("Object")) reader.read_object(obj, out);
}

}  // namespace ecat::esi
