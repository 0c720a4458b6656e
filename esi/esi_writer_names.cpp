#include "esi/esi_writer_names.hpp"

#include <array>
#include <cctype>
#include <charconv>

#include <fmt/format.h>

namespace ecat::esi {
namespace {

using od::Access;

constexpr std::uint16_t kBitsPerByte = 8;
constexpr std::uint16_t kBitsPerUnicodeChar = 16;

// Restriction words of ETG.2000 AccessType for each subset of {PreOp, SafeOp, Op};
// the full set has no restriction, the empty set is not expressible.
struct Restriction {
  std::uint16_t states;  // kReadPreOp/kReadSafeOp/kReadOp layout
  std::string_view word;
};
constexpr std::array kRestrictions = {
    Restriction{Access::kReadPreOp, "PreOP"},
    Restriction{Access::kReadPreOp | Access::kReadSafeOp, "PreOP_SafeOP"},
    Restriction{Access::kReadPreOp | Access::kReadOp, "PreOP_OP"},
    Restriction{Access::kReadSafeOp, "SafeOP"},
    Restriction{Access::kReadSafeOp | Access::kReadOp, "SafeOP_OP"},
    Restriction{Access::kReadOp, "OP"},
};
constexpr int kWriteShift = 3;  // kWritePreOp == kReadPreOp << 3

std::string_view restriction_word(std::uint16_t states) {
  for (const auto& r : kRestrictions) {
    if (r.states == states) return r.word;
  }
  return {};
}

std::optional<std::uint16_t> restriction_states(std::string_view word) {
  if (word.empty()) return Access::kReadAll;
  if (word == "PreOp") return Access::kReadPreOp;  // spelling also allowed by the schema
  for (const auto& r : kRestrictions) {
    if (r.word == word) return r.states;
  }
  return std::nullopt;
}

std::optional<std::uint32_t> number_in(std::string_view text) {
  std::uint32_t v = 0;
  auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc{} || p != text.data() + text.size()) return std::nullopt;
  return v;
}

}  // namespace

std::string esi_hex(std::uint64_t value, int digits) {
  return fmt::format("#x{:0{}X}", value, digits);
}

std::string hex_binary(const od::Value& bytes) {
  std::string out;
  out.reserve(bytes.size() * 2);
  for (auto b : bytes) out += fmt::format("{:02X}", b);
  return out;
}

std::optional<od::Value> parse_hex_binary(std::string_view text) {
  if (text.size() % 2 != 0) return std::nullopt;
  od::Value out;
  for (std::size_t i = 0; i < text.size(); i += 2) {
    std::uint8_t b = 0;
    auto [p, ec] = std::from_chars(text.data() + i, text.data() + i + 2, b, 16);
    if (ec != std::errc{} || p != text.data() + i + 2) return std::nullopt;
    out.push_back(b);
  }
  return out;
}

std::string esi_entry_type_name(od::DataType type, std::uint16_t bit_length) {
  switch (type) {
    case od::DataType::VisibleString:
      return fmt::format("STRING({})", bit_length / kBitsPerByte);
    case od::DataType::UnicodeString:
      return fmt::format("UNICODE_STRING({})", bit_length / kBitsPerUnicodeChar);
    case od::DataType::OctetString: {
      const int n = bit_length / kBitsPerByte;
      return n > 0 ? fmt::format("ARRAY [0..{}] OF BYTE", n - 1) : std::string("OCTET_STRING");
    }
    default: return std::string(od::esi_base_name(type));
  }
}

std::optional<EsiTypeName> parse_esi_type_name(std::string_view name) {
  auto inside = [&](std::string_view prefix, std::string_view suffix) -> std::optional<std::uint32_t> {
    if (name.size() <= prefix.size() + suffix.size() || !name.starts_with(prefix) ||
        !name.ends_with(suffix)) {
      return std::nullopt;
    }
    return number_in(name.substr(prefix.size(), name.size() - prefix.size() - suffix.size()));
  };
  if (auto n = inside("STRING(", ")")) {
    return EsiTypeName{od::DataType::VisibleString, static_cast<std::uint16_t>(*n * kBitsPerByte)};
  }
  if (auto n = inside("UNICODE_STRING(", ")")) {
    return EsiTypeName{od::DataType::UnicodeString,
                       static_cast<std::uint16_t>(*n * kBitsPerUnicodeChar)};
  }
  for (std::string_view base : {"BYTE", "USINT"}) {
    const std::string suffix = fmt::format("] OF {}", base);
    if (auto n = inside("ARRAY [0..", suffix)) {
      return EsiTypeName{od::DataType::OctetString,
                         static_cast<std::uint16_t>((*n + 1) * kBitsPerByte)};
    }
  }
  if (name == "BOOLEAN") return EsiTypeName{od::DataType::Boolean, 0};
  if (auto t = od::from_esi_base_name(name)) return EsiTypeName{*t, 0};
  return std::nullopt;
}

EsiAccess esi_access(const od::Access& a) {
  EsiAccess out;
  const std::uint16_t read = a.bits & Access::kReadAll;
  const std::uint16_t write = static_cast<std::uint16_t>((a.bits & Access::kWriteAll) >> kWriteShift);
  out.access = read && write ? "rw" : write ? "wo" : "ro";
  if (read && read != Access::kReadAll) out.read_restrictions = restriction_word(read);
  if (write && write != Access::kReadAll) out.write_restrictions = restriction_word(write);
  return out;
}

std::optional<std::uint16_t> parse_esi_access(std::string_view access,
                                              std::string_view read_restrictions,
                                              std::string_view write_restrictions) {
  auto read = restriction_states(read_restrictions);
  auto write = restriction_states(write_restrictions);
  if (!read || !write) return std::nullopt;
  if (access == "ro") return *read;
  if (access == "wo") return static_cast<std::uint16_t>(*write << kWriteShift);
  if (access == "rw") return static_cast<std::uint16_t>(*read | (*write << kWriteShift));
  return std::nullopt;
}

std::string esi_pdo_mapping(const od::Access& a) {
  std::string out;
  if (a.rx_mappable()) out += 'R';
  if (a.tx_mappable()) out += 'T';
  return out;
}

std::optional<std::uint16_t> parse_esi_pdo_mapping(std::string_view text) {
  std::uint16_t bits = 0;
  for (char c : text) {
    switch (std::toupper(static_cast<unsigned char>(c))) {
      case 'R': bits |= Access::kRxPdoMappable; break;
      case 'T': bits |= Access::kTxPdoMappable; break;
      default: return std::nullopt;
    }
  }
  return bits;
}

}  // namespace ecat::esi
