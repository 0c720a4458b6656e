// Text -> wire value conversion for device files: numbers in decimal,
// 0x.. or #x.. hex; values of every CiA 301 basic type encoded as the
// little-endian bytes that go on the wire (CiA 301 §7.1, ETG.1000.6 §5.6).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "common/expected.hpp"
#include "od/data_type.hpp"
#include "od/object.hpp"

namespace ecat::esi {

// A parsed integer literal: sign and magnitude, so the full UNSIGNED64 and
// INTEGER64 ranges both fit.
struct IntegerLiteral {
  bool negative = false;
  std::uint64_t magnitude = 0;
  bool hex = false;
};

// "-12", "0x1C12", "#x1C12", "+7". nullopt if not a number or too large.
std::optional<IntegerLiteral> parse_integer(std::string_view text) noexcept;

// A non-negative number that must fit `max` (e.g. an index or a size).
std::optional<std::uint64_t> parse_unsigned(std::string_view text, std::uint64_t max) noexcept;
// A signed number in int32 range (cycle factors, shift times, homing methods).
std::optional<std::int64_t> parse_signed(std::string_view text, std::int64_t min,
                                         std::int64_t max) noexcept;

std::optional<bool> parse_bool(std::string_view text) noexcept;

// The size in bits of an entry of `type`; strings and octet strings take
// `length_bytes`. 0 for types that cannot hold a value (structured ones).
std::uint16_t entry_bit_length(od::DataType type, std::uint32_t length_bytes) noexcept;

// Encodes `text` as a value of `type` with `bit_length` bits. Integer types
// accept decimal in the type's range, or hex that fits the bit length (two's
// complement for signed types: INTEGER8 "#xFF" is -1). Strings must not be
// longer than bit_length / 8 bytes. The error says why, without location.
Expected<od::Value, std::string> encode_value(od::DataType type, std::uint16_t bit_length,
                                              std::string_view text);

// The zero value ("not given") of an entry.
od::Value zero_value(od::DataType type, std::uint16_t bit_length);

// Little-endian encoding of an unsigned number into `bytes` bytes.
od::Value le_bytes(std::uint64_t value, std::size_t bytes);

// Orders two numeric values of `type` (<0, 0, >0). Non-numeric types: 0.
int compare_values(od::DataType type, const od::Value& a, const od::Value& b) noexcept;

// Whether min/max make sense for `type` (integers, reals, bit types).
bool is_numeric(od::DataType type) noexcept;

}  // namespace ecat::esi
