// The type of a value known only by its bit length (a PDO entry without a
// dictionary object, in a vendor file's twin or a captured device).
#pragma once

#include <optional>

#include "od/data_type.hpp"

namespace ecat::od {

// BOOLEAN, BIT2..BIT7 or UNSIGNEDn for 8, 16, 24, 32 and 64 bits; none for
// other lengths.
constexpr std::optional<DataType> unsigned_type_of_bits(unsigned bits) noexcept {
  switch (bits) {
    case 1: return DataType::Boolean;
    case 2: return DataType::Bit2;
    case 3: return DataType::Bit3;
    case 4: return DataType::Bit4;
    case 5: return DataType::Bit5;
    case 6: return DataType::Bit6;
    case 7: return DataType::Bit7;
    case 8: return DataType::Unsigned8;
    case 16: return DataType::Unsigned16;
    case 24: return DataType::Unsigned24;
    case 32: return DataType::Unsigned32;
    case 64: return DataType::Unsigned64;
    default: return std::nullopt;
  }
}

}  // namespace ecat::od
