#include "coe/value.hpp"

#include <algorithm>
#include <bit>

namespace ecat::coe {

bool is_numeric(od::DataType type) noexcept {
  return !od::is_string(type) && od::fixed_bit_size(type) != 0 && od::fixed_bit_size(type) <= 64;
}

std::uint64_t load_bits(ConstBytes bytes, unsigned bits, bool is_signed) noexcept {
  std::uint64_t v = 0;
  const std::size_t n = std::min<std::size_t>(bytes.size(), 8);
  for (std::size_t i = 0; i < n; ++i) v |= static_cast<std::uint64_t>(bytes[i]) << (8 * i);
  if (bits > 0 && bits < 64) {
    const std::uint64_t mask = (std::uint64_t{1} << bits) - 1;
    v &= mask;
    if (is_signed && (v >> (bits - 1)) & 1u) v |= ~mask;
  }
  return v;
}

namespace {

template <typename T>
int order(T a, T b) noexcept {
  return a < b ? -1 : (b < a ? 1 : 0);
}

}  // namespace

int compare_values(od::DataType type, ConstBytes a, ConstBytes b) noexcept {
  const unsigned bits = od::fixed_bit_size(type);
  if (type == od::DataType::Real32) {
    return order(std::bit_cast<float>(static_cast<std::uint32_t>(load_bits(a, 32, false))),
                 std::bit_cast<float>(static_cast<std::uint32_t>(load_bits(b, 32, false))));
  }
  if (type == od::DataType::Real64) {
    return order(std::bit_cast<double>(load_bits(a, 64, false)),
                 std::bit_cast<double>(load_bits(b, 64, false)));
  }
  if (od::is_signed(type)) {
    return order(static_cast<std::int64_t>(load_bits(a, bits, true)),
                 static_cast<std::int64_t>(load_bits(b, bits, true)));
  }
  return order(load_bits(a, bits, false), load_bits(b, bits, false));
}

}  // namespace ecat::coe
