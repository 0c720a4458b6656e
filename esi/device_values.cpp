#include "esi/device_values.hpp"

#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>

#include <fmt/format.h>

namespace ecat::esi {
namespace {

constexpr unsigned kBitsPerByte = 8;
constexpr std::uint64_t kHexBase = 16;
constexpr std::uint64_t kDecimalBase = 10;

std::string_view trim(std::string_view s) noexcept {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::optional<unsigned> hex_digit(char c) noexcept {
  if (c >= '0' && c <= '9') return static_cast<unsigned>(c - '0');
  if (c >= 'a' && c <= 'f') return static_cast<unsigned>(c - 'a' + 10);
  if (c >= 'A' && c <= 'F') return static_cast<unsigned>(c - 'A' + 10);
  return std::nullopt;
}

bool is_integer_type(od::DataType t) noexcept {
  return !od::is_real(t) && !od::is_string(t) && od::fixed_bit_size(t) > 0 &&
         od::fixed_bit_size(t) <= 64;
}

std::size_t byte_size(std::uint16_t bits) noexcept {
  return (bits + kBitsPerByte - 1) / kBitsPerByte;
}

std::uint64_t decode_unsigned(const od::Value& v) noexcept {
  std::uint64_t x = 0;
  for (std::size_t i = v.size(); i-- > 0;) x = (x << kBitsPerByte) | v[i];
  return x;
}

std::int64_t decode_signed(const od::Value& v, std::uint16_t bits) noexcept {
  std::uint64_t x = decode_unsigned(v);
  if (bits < 64 && bits > 0 && (x >> (bits - 1)) & 1u) x |= ~std::uint64_t{0} << bits;
  return static_cast<std::int64_t>(x);
}

double decode_real(od::DataType t, const od::Value& v) noexcept {
  if (t == od::DataType::Real32) {
    return static_cast<double>(std::bit_cast<float>(static_cast<std::uint32_t>(decode_unsigned(v))));
  }
  return std::bit_cast<double>(decode_unsigned(v));
}

Expected<od::Value, std::string> encode_integer(od::DataType type, std::uint16_t bits,
                                                std::string_view text) {
  if (type == od::DataType::Boolean) {
    if (auto b = parse_bool(text)) return le_bytes(*b ? 1u : 0u, 1);
    return fail(fmt::format("'{}' is not a BOOLEAN (true/false/1/0)", text));
  }
  auto lit = parse_integer(text);
  if (!lit) return fail(fmt::format("'{}' is not a number", text));
  const std::string_view type_name = od::canopen_name(type);
  const std::uint64_t mask = bits >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << bits) - 1;
  std::uint64_t raw = 0;
  if (od::is_signed(type) && !lit->hex) {
    const std::uint64_t max_pos = mask >> 1;
    const std::uint64_t max_neg = max_pos + 1;
    if ((lit->negative && lit->magnitude > max_neg) || (!lit->negative && lit->magnitude > max_pos)) {
      return fail(fmt::format("value {} does not fit {}", text, type_name));
    }
    raw = lit->negative ? (~lit->magnitude + 1) & mask : lit->magnitude;
  } else {
    if ((lit->negative && lit->magnitude != 0) || lit->magnitude > mask) {
      return fail(fmt::format("value {} does not fit {}", text, type_name));
    }
    raw = lit->magnitude;
  }
  return le_bytes(raw, byte_size(bits));
}

Expected<od::Value, std::string> encode_real(od::DataType type, std::string_view text) {
  const std::string_view t = trim(text);
  // "#x" + the little-endian bytes' hex: the exact bit pattern, the form the
  // device XML writer uses for values without a decimal spelling (NaN, +-inf;
  // docs/device-format.md "Values").
  if (t.starts_with("#x")) {
    const std::size_t bytes = type == od::DataType::Real32 ? sizeof(float) : sizeof(double);
    std::uint64_t raw = 0;
    auto [e, err] = std::from_chars(t.data() + 2, t.data() + t.size(), raw, 16);
    if (err != std::errc{} || e != t.data() + t.size() || t.size() - 2 > 2 * bytes) {
      return fail(fmt::format("'{}' is not a {} bit pattern", text, od::canopen_name(type)));
    }
    return le_bytes(raw, bytes);
  }
  double d = 0;
  auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), d);
  if (ec != std::errc{} || end != t.data() + t.size() || !std::isfinite(d)) {
    return fail(fmt::format("'{}' is not a {} number", text, od::canopen_name(type)));
  }
  if (type == od::DataType::Real32) {
    if (std::fabs(d) > static_cast<double>(std::numeric_limits<float>::max())) {
      return fail(fmt::format("value {} does not fit REAL32", text));
    }
    return le_bytes(std::bit_cast<std::uint32_t>(static_cast<float>(d)), sizeof(float));
  }
  return le_bytes(std::bit_cast<std::uint64_t>(d), sizeof(double));
}

Expected<od::Value, std::string> encode_octets(std::string_view text, std::size_t max_bytes) {
  std::string_view t = trim(text);
  if (t.starts_with("#x") || t.starts_with("0x") || t.starts_with("#X") || t.starts_with("0X")) {
    t.remove_prefix(2);
  }
  od::Value out;
  // High nibble of the byte being read; a plain flag rather than an optional,
  // which GCC's -O2 -Wmaybe-uninitialized misreads.
  unsigned high = 0;
  bool have_high = false;
  for (char c : t) {
    if (std::isspace(static_cast<unsigned char>(c))) continue;
    auto d = hex_digit(c);
    if (!d) return fail(fmt::format("'{}' is not a hex byte string", text));
    if (have_high) {
      out.push_back(static_cast<std::uint8_t>((high << 4) | *d));
      have_high = false;
    } else {
      high = *d;
      have_high = true;
    }
  }
  if (have_high) return fail(fmt::format("'{}' has an odd number of hex digits", text));
  if (out.size() > max_bytes) {
    return fail(fmt::format("value is {} bytes, longer than its length {}", out.size(), max_bytes));
  }
  return out;
}

Expected<od::Value, std::string> encode_string(od::DataType type, std::string_view text,
                                               std::size_t max_bytes) {
  od::Value out;
  for (char c : text) {
    if (type == od::DataType::UnicodeString) {
      if (static_cast<unsigned char>(c) >= 0x80) {
        return fail(std::string("UNICODE_STRING defaults must be ASCII"));
      }
      out.push_back(static_cast<std::uint8_t>(c));
      out.push_back(0);  // UTF-16LE high byte
    } else {
      out.push_back(static_cast<std::uint8_t>(c));
    }
  }
  if (out.size() > max_bytes) {
    return fail(fmt::format("string '{}' is {} bytes, longer than its length {}", text, out.size(),
                            max_bytes));
  }
  return out;
}

}  // namespace

std::optional<IntegerLiteral> parse_integer(std::string_view text) noexcept {
  std::string_view t = trim(text);
  IntegerLiteral lit;
  if (!t.empty() && (t.front() == '-' || t.front() == '+')) {
    lit.negative = t.front() == '-';
    t.remove_prefix(1);
  }
  std::uint64_t base = kDecimalBase;
  if (t.size() > 2 && (t[0] == '0' || t[0] == '#') && (t[1] == 'x' || t[1] == 'X')) {
    base = kHexBase;
    lit.hex = true;
    t.remove_prefix(2);
  }
  if (t.empty()) return std::nullopt;
  for (char c : t) {
    auto d = hex_digit(c);
    if (!d || *d >= base) return std::nullopt;
    if (lit.magnitude > (std::numeric_limits<std::uint64_t>::max() - *d) / base) return std::nullopt;
    lit.magnitude = lit.magnitude * base + *d;
  }
  return lit;
}

std::optional<std::uint64_t> parse_unsigned(std::string_view text, std::uint64_t max) noexcept {
  auto lit = parse_integer(text);
  if (!lit || (lit->negative && lit->magnitude != 0) || lit->magnitude > max) return std::nullopt;
  return lit->magnitude;
}

std::optional<std::int64_t> parse_signed(std::string_view text, std::int64_t min,
                                         std::int64_t max) noexcept {
  auto lit = parse_integer(text);
  if (!lit || lit->magnitude > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
    return std::nullopt;
  }
  const auto v = static_cast<std::int64_t>(lit->magnitude);
  const std::int64_t s = lit->negative ? -v : v;
  if (s < min || s > max) return std::nullopt;
  return s;
}

std::optional<bool> parse_bool(std::string_view text) noexcept {
  const std::string_view t = trim(text);
  if (t == "true" || t == "1") return true;
  if (t == "false" || t == "0") return false;
  return std::nullopt;
}

std::uint16_t entry_bit_length(od::DataType type, std::uint32_t length_bytes) noexcept {
  if (od::is_string(type)) return static_cast<std::uint16_t>(length_bytes * kBitsPerByte);
  return od::fixed_bit_size(type);
}

od::Value le_bytes(std::uint64_t value, std::size_t bytes) {
  od::Value out(bytes, 0);
  for (std::size_t i = 0; i < bytes && i < sizeof(value); ++i) {
    out[i] = static_cast<std::uint8_t>(value >> (kBitsPerByte * i));
  }
  return out;
}

od::Value zero_value(od::DataType type, std::uint16_t bit_length) {
  if (od::is_string(type)) return {};
  return od::Value(byte_size(bit_length), 0);
}

Expected<od::Value, std::string> encode_value(od::DataType type, std::uint16_t bit_length,
                                              std::string_view text) {
  const std::size_t max_bytes = bit_length / kBitsPerByte;
  if (type == od::DataType::VisibleString || type == od::DataType::UnicodeString) {
    return encode_string(type, text, max_bytes);
  }
  if (type == od::DataType::OctetString || type == od::DataType::Domain ||
      type == od::DataType::Guid) {
    return encode_octets(text, byte_size(bit_length));
  }
  if (od::is_real(type)) return encode_real(type, text);
  if (is_integer_type(type)) return encode_integer(type, bit_length, text);
  return fail(fmt::format("type {} cannot hold a value", od::canopen_name(type)));
}

bool is_numeric(od::DataType type) noexcept {
  return od::is_real(type) || is_integer_type(type);
}

int compare_values(od::DataType type, const od::Value& a, const od::Value& b) noexcept {
  if (od::is_real(type)) {
    const double x = decode_real(type, a), y = decode_real(type, b);
    return x < y ? -1 : (x > y ? 1 : 0);
  }
  if (!is_integer_type(type)) return 0;
  if (od::is_signed(type)) {
    const std::uint16_t bits = od::fixed_bit_size(type);
    const std::int64_t x = decode_signed(a, bits), y = decode_signed(b, bits);
    return x < y ? -1 : (x > y ? 1 : 0);
  }
  const std::uint64_t x = decode_unsigned(a), y = decode_unsigned(b);
  return x < y ? -1 : (x > y ? 1 : 0);
}

}  // namespace ecat::esi
