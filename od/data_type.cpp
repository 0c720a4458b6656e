#include "od/data_type.hpp"

#include <array>
#include <utility>

namespace ecat::od {
namespace {

struct TypeNames {
  DataType type;
  std::string_view canopen;
  std::string_view esi;
};

constexpr std::array kNames = {
    TypeNames{DataType::Boolean, "BOOLEAN", "BOOL"},
    TypeNames{DataType::Integer8, "INTEGER8", "SINT"},
    TypeNames{DataType::Integer16, "INTEGER16", "INT"},
    TypeNames{DataType::Integer32, "INTEGER32", "DINT"},
    TypeNames{DataType::Unsigned8, "UNSIGNED8", "USINT"},
    TypeNames{DataType::Unsigned16, "UNSIGNED16", "UINT"},
    TypeNames{DataType::Unsigned32, "UNSIGNED32", "UDINT"},
    TypeNames{DataType::Real32, "REAL32", "REAL"},
    TypeNames{DataType::VisibleString, "VISIBLE_STRING", "STRING"},
    TypeNames{DataType::OctetString, "OCTET_STRING", "OCTET_STRING"},
    TypeNames{DataType::UnicodeString, "UNICODE_STRING", "UNICODE_STRING"},
    TypeNames{DataType::TimeOfDay, "TIME_OF_DAY", "TIME_OF_DAY"},
    TypeNames{DataType::TimeDifference, "TIME_DIFFERENCE", "TIME_DIFFERENCE"},
    TypeNames{DataType::Domain, "DOMAIN", "DOMAIN"},
    TypeNames{DataType::Integer24, "INTEGER24", "INT24"},
    TypeNames{DataType::Real64, "REAL64", "LREAL"},
    TypeNames{DataType::Integer40, "INTEGER40", "INT40"},
    TypeNames{DataType::Integer48, "INTEGER48", "INT48"},
    TypeNames{DataType::Integer56, "INTEGER56", "INT56"},
    TypeNames{DataType::Integer64, "INTEGER64", "LINT"},
    TypeNames{DataType::Unsigned24, "UNSIGNED24", "UINT24"},
    TypeNames{DataType::Unsigned40, "UNSIGNED40", "UINT40"},
    TypeNames{DataType::Unsigned48, "UNSIGNED48", "UINT48"},
    TypeNames{DataType::Unsigned56, "UNSIGNED56", "UINT56"},
    TypeNames{DataType::Unsigned64, "UNSIGNED64", "ULINT"},
    TypeNames{DataType::Guid, "GUID", "GUID"},
    TypeNames{DataType::Byte, "BYTE", "BYTE"},
    TypeNames{DataType::Word, "WORD", "WORD"},
    TypeNames{DataType::Dword, "DWORD", "DWORD"},
    TypeNames{DataType::BitArr8, "BITARR8", "BITARR8"},
    TypeNames{DataType::BitArr16, "BITARR16", "BITARR16"},
    TypeNames{DataType::BitArr32, "BITARR32", "BITARR32"},
    TypeNames{DataType::Bit1, "BIT1", "BIT1"},
    TypeNames{DataType::Bit2, "BIT2", "BIT2"},
    TypeNames{DataType::Bit3, "BIT3", "BIT3"},
    TypeNames{DataType::Bit4, "BIT4", "BIT4"},
    TypeNames{DataType::Bit5, "BIT5", "BIT5"},
    TypeNames{DataType::Bit6, "BIT6", "BIT6"},
    TypeNames{DataType::Bit7, "BIT7", "BIT7"},
    TypeNames{DataType::Bit8, "BIT8", "BIT8"},
};

}  // namespace

std::string_view canopen_name(DataType t) noexcept {
  for (const auto& n : kNames) {
    if (n.type == t) return n.canopen;
  }
  return {};
}

std::optional<DataType> from_canopen_name(std::string_view name) noexcept {
  for (const auto& n : kNames) {
    if (n.canopen == name) return n.type;
  }
  return std::nullopt;
}

std::string_view esi_base_name(DataType t) noexcept {
  for (const auto& n : kNames) {
    if (n.type == t) return n.esi;
  }
  return {};
}

std::optional<DataType> from_esi_base_name(std::string_view name) noexcept {
  for (const auto& n : kNames) {
    if (n.esi == name) return n.type;
  }
  return std::nullopt;
}

}  // namespace ecat::od
