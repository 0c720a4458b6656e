// Numeric view of stored entry values: the little-endian bytes of a CANopen
// basic type (CiA 301 §7.1) decoded for range checks against the minimum and
// maximum the dictionary gives (abort 06090031h/06090032h, CiA 301 §7.2.4.3.17).
#pragma once

#include <cstdint>

#include "common/le.hpp"
#include "od/data_type.hpp"

namespace ecat::coe {

// True for types whose values order as numbers (integers, reals, bit fields).
bool is_numeric(od::DataType type) noexcept;

// -1, 0, 1 as a <, ==, > b, both encoded as `type` (missing high bytes are 0).
int compare_values(od::DataType type, ConstBytes a, ConstBytes b) noexcept;

// Loads up to 8 little-endian bytes; sign-extends from `bits` when `is_signed`.
std::uint64_t load_bits(ConstBytes bytes, unsigned bits, bool is_signed) noexcept;

}  // namespace ecat::coe
