#include "control/object_access.hpp"

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "coe/object_store.hpp"
#include "coe/value.hpp"
#include "od/data_type.hpp"
#include "od/device.hpp"

namespace ecat::control {
namespace {

using nlohmann::json;
using Slot = coe::ObjectStore::Slot;

std::string to_hex(ConstBytes bytes) {
  std::string out;
  out.reserve(2 * bytes.size());
  for (std::uint8_t b : bytes) out += fmt::format("{:02x}", b);
  return out;
}

Expected<std::vector<std::uint8_t>, ControlError> from_hex(std::string_view text) {
  auto nibble = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  if (text.size() % 2 != 0) {
    return fail(control_error(error_code::kBadValue, "hex: an even number of hex digits is needed"));
  }
  std::vector<std::uint8_t> out;
  for (std::size_t i = 0; i < text.size(); i += 2) {
    const int hi = nibble(text[i]);
    const int lo = nibble(text[i + 1]);
    if (hi < 0 || lo < 0) return fail(control_error(error_code::kBadValue, "hex: not a hex digit"));
    out.push_back(static_cast<std::uint8_t>(hi << 4 | lo));
  }
  return out;
}

std::string where(std::uint16_t index, std::uint8_t subindex) { return fmt::format("{:04X}h:{:02X}h", index, subindex); }

bool is_integer_type(od::DataType t) { return coe::is_numeric(t) && !od::is_real(t) && t != od::DataType::Boolean; }

// Bits of the value: the type's fixed size, or the entry's (BITn, BYTE ...).
unsigned value_bits(const od::Entry& e) {
  const unsigned fixed = od::fixed_bit_size(e.type);
  return fixed != 0 ? fixed : e.bit_length;
}

json decode(const od::Entry& e, ConstBytes bytes) {
  if (e.type == od::DataType::Boolean) return !bytes.empty() && (bytes[0] & 1) != 0;
  if (e.type == od::DataType::Real32 && bytes.size() >= 4) {
    return static_cast<double>(std::bit_cast<float>(static_cast<std::uint32_t>(coe::load_bits(bytes, 32, false))));
  }
  if (e.type == od::DataType::Real64 && bytes.size() >= 8) {
    return std::bit_cast<double>(coe::load_bits(bytes, 64, false));
  }
  if (is_integer_type(e.type) && bytes.size() <= 8) {
    const unsigned bits = std::min<unsigned>(value_bits(e), static_cast<unsigned>(8 * bytes.size()));
    const std::uint64_t raw = coe::load_bits(bytes, bits, od::is_signed(e.type));
    if (od::is_signed(e.type)) return static_cast<std::int64_t>(raw);
    return raw;
  }
  if (e.type == od::DataType::VisibleString) {
    std::string s(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    return s.substr(0, s.find('\0'));
  }
  return to_hex(bytes);
}

Expected<std::vector<std::uint8_t>, ControlError> encode_integer(const od::Entry& e, const Slot& s, const json& v,
                                                                 const std::string& at) {
  if (!v.is_number_integer()) {
    return fail(control_error(error_code::kBadValue,
                              fmt::format("{} is {}: an integer is needed", at, od::canopen_name(e.type))));
  }
  const unsigned bits = value_bits(e);
  std::uint64_t raw = 0;
  if (od::is_signed(e.type)) {
    if (v.is_number_unsigned() && v.get<std::uint64_t>() > static_cast<std::uint64_t>(INT64_MAX)) {
      return fail(control_error(error_code::kOutOfRange, fmt::format("{}: {} does not fit {}", at, v.dump(),
                                                                     od::canopen_name(e.type))));
    }
    const std::int64_t x = v.get<std::int64_t>();
    if (bits < 64) {
      const std::int64_t lo = -(std::int64_t{1} << (bits - 1));
      const std::int64_t hi = (std::int64_t{1} << (bits - 1)) - 1;
      if (x < lo || x > hi) {
        return fail(control_error(error_code::kOutOfRange, fmt::format("{}: {} is outside {} ({}..{})", at, x,
                                                                       od::canopen_name(e.type), lo, hi)));
      }
    }
    raw = static_cast<std::uint64_t>(x);
  } else {
    if (!v.is_number_unsigned() && v.get<std::int64_t>() < 0) {
      return fail(control_error(error_code::kOutOfRange,
                                fmt::format("{}: {} is negative, {} is unsigned", at, v.dump(), od::canopen_name(e.type))));
    }
    raw = v.get<std::uint64_t>();
    if (bits < 64 && (raw >> bits) != 0) {
      return fail(control_error(error_code::kOutOfRange, fmt::format("{}: {} is outside {} (0..{})", at, raw,
                                                                     od::canopen_name(e.type),
                                                                     (std::uint64_t{1} << bits) - 1)));
    }
  }
  std::vector<std::uint8_t> out(s.capacity);
  for (std::size_t i = 0; i < out.size() && i < 8; ++i) out[i] = static_cast<std::uint8_t>(raw >> (8 * i));
  return out;
}

Expected<std::vector<std::uint8_t>, ControlError> encode(const od::Entry& e, const Slot& s, const json& v,
                                                         const std::string& at) {
  if (v.is_object()) {
    if (v.size() != 1 || !v.contains("hex") || !v["hex"].is_string()) {
      return fail(control_error(error_code::kBadValue, at + ": an object value must be {\"hex\": \"...\"}"));
    }
    return from_hex(v["hex"].get<std::string>());
  }
  if (e.type == od::DataType::Boolean) {
    if (v.is_boolean()) return std::vector<std::uint8_t>{static_cast<std::uint8_t>(v.get<bool>() ? 1 : 0)};
    if (v.is_number_integer() && (v.get<std::int64_t>() == 0 || v.get<std::int64_t>() == 1)) {
      return std::vector<std::uint8_t>{static_cast<std::uint8_t>(v.get<std::int64_t>())};
    }
    return fail(control_error(error_code::kBadValue, at + " is BOOLEAN: true, false, 0 or 1 is needed"));
  }
  if (od::is_real(e.type)) {
    if (!v.is_number()) {
      return fail(control_error(error_code::kBadValue, fmt::format("{} is {}: a number is needed", at,
                                                                   od::canopen_name(e.type))));
    }
    const double x = v.get<double>();
    std::uint64_t raw = 0;
    if (e.type == od::DataType::Real32) {
      if (std::abs(x) > static_cast<double>(std::numeric_limits<float>::max())) {
        return fail(control_error(error_code::kOutOfRange, fmt::format("{}: {} does not fit REAL32", at, x)));
      }
      raw = std::bit_cast<std::uint32_t>(static_cast<float>(x));
    } else {
      raw = std::bit_cast<std::uint64_t>(x);
    }
    std::vector<std::uint8_t> out(s.capacity);
    for (std::size_t i = 0; i < out.size() && i < 8; ++i) out[i] = static_cast<std::uint8_t>(raw >> (8 * i));
    return out;
  }
  if (is_integer_type(e.type)) return encode_integer(e, s, v, at);
  if (e.type == od::DataType::VisibleString) {
    if (!v.is_string()) return fail(control_error(error_code::kBadValue, at + " is VISIBLE_STRING: a string is needed"));
    const std::string text = v.get<std::string>();
    return std::vector<std::uint8_t>(text.begin(), text.end());
  }
  if (!v.is_string()) {
    return fail(control_error(error_code::kBadValue,
                              fmt::format("{} is {}: a hex string is needed", at, od::canopen_name(e.type))));
  }
  return from_hex(v.get<std::string>());
}

ControlError missing(const coe::ObjectStore& store, std::uint16_t index, std::uint8_t subindex) {
  if (!store.contains(index)) {
    return control_error(error_code::kUnknownObject, fmt::format("no object {:04X}h in the dictionary", index));
  }
  return control_error(error_code::kUnknownSubindex, fmt::format("object {:04X}h has no subindex {}", index, subindex));
}

json describe_entry(const coe::ObjectStore& store, const Slot& s, std::uint16_t index, std::uint8_t subindex) {
  const ConstBytes bytes = store.value(s);
  return json{{"index", index},
              {"subindex", subindex},
              {"name", s.entry->name},
              {"type", std::string(od::canopen_name(s.entry->type))},
              {"value", decode(*s.entry, bytes)},
              {"hex", to_hex(bytes)}};
}

}  // namespace

Expected<json, ControlError> read_object(const coe::ObjectStore& store, std::uint16_t index, std::uint8_t subindex) {
  const Slot* s = store.slot(index, subindex);
  if (!s) return fail(missing(store, index, subindex));
  return describe_entry(store, *s, index, subindex);
}

Expected<json, ControlError> write_object(coe::ObjectStore& store, std::uint16_t index, std::uint8_t subindex,
                                          const json& value) {
  Slot* s = store.slot(index, subindex);
  if (!s) return fail(missing(store, index, subindex));
  const std::string at = where(index, subindex);
  if (s->entry->access.is_const) {
    return fail(control_error(error_code::kReadOnly, at + " is a constant of the device (const): never written"));
  }
  auto bytes = encode(*s->entry, *s, value, at);
  if (!bytes) return fail(bytes.error());
  if (auto ok = store.check(*s, *bytes); !ok) {
    switch (ok.error()) {
      case coe::SdoAbort::ValueTooHigh:
      case coe::SdoAbort::ValueTooLow:
      case coe::SdoAbort::ValueRange:
        return fail(control_error(error_code::kOutOfRange,
                                  fmt::format("{}: {} is outside the dictionary's range ({}): {}", at, value.dump(),
                                              s->entry->name, coe::describe(ok.error()))));
      default:
        return fail(control_error(error_code::kBadValue, fmt::format("{}: {} bytes for a {}-byte entry: {}", at,
                                                                     bytes->size(), std::uint32_t{s->capacity},
                                                                     coe::describe(ok.error()))));
    }
  }
  if (auto ok = store.assign(*s, *bytes); !ok) {
    return fail(control_error(error_code::kBadValue, fmt::format("{}: {}", at, coe::describe(ok.error()))));
  }
  return describe_entry(store, *s, index, subindex);
}

Expected<NamedPdoEntry, ControlError> find_pdo_entry(const od::DeviceDescription& device, std::string_view name) {
  std::vector<NamedPdoEntry> found;
  // The entry's name alone, else "PDO name/entry name" split at each '/'
  // (PDO names such as "Inputs (CSP/CSV/CST)" have slashes of their own).
  auto collect = [&](std::optional<std::string_view> pdo_name, std::string_view entry_name) {
    for (const auto* list : {&device.rx_pdos, &device.tx_pdos}) {
      for (const od::Pdo& p : *list) {
        if (pdo_name && p.name != *pdo_name) continue;
        for (const od::PdoEntry& e : p.entries) {
          if (e.index != 0 && e.name == entry_name) found.push_back({&e, p.is_rx(), p.index});
        }
      }
    }
  };
  collect(std::nullopt, name);
  for (std::size_t slash = name.find('/'); found.empty() && slash != std::string_view::npos;
       slash = name.find('/', slash + 1)) {
    collect(name.substr(0, slash), name.substr(slash + 1));
  }
  if (found.empty()) {
    return fail(control_error(error_code::kUnknownPdoEntry,
                              fmt::format("no process-data entry '{}' in the device's PDOs", name)));
  }
  if (found.size() > 1) {
    return fail(control_error(error_code::kBadRequest,
                              fmt::format("'{}' names {} process-data entries: use \"PDO name/entry name\"", name,
                                          found.size())));
  }
  return found.front();
}

json list_pdo_entries(const od::DeviceDescription& device, const coe::ObjectStore& store) {
  json out = json::array();
  for (const auto* list : {&device.rx_pdos, &device.tx_pdos}) {
    for (const od::Pdo& p : *list) {
      for (const od::PdoEntry& e : p.entries) {
        if (e.index == 0) continue;
        json row{{"pdo", p.index},          {"pdo_name", p.name},   {"direction", p.is_rx() ? "rx" : "tx"},
                 {"name", e.name},          {"index", e.index},     {"subindex", e.subindex},
                 {"bit_length", e.bit_length}};
        if (auto v = read_object(store, e.index, e.subindex)) row["value"] = (*v)["value"];
        out.push_back(std::move(row));
      }
    }
  }
  return out;
}

}  // namespace ecat::control
