// CANopen / ETG.1000.6 basic data types: the DEFTYPE indices (ETG.1000.6
// Table 64, CiA 301 §7.4.7) that SDO information and the ESI use.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace ecat::od {

enum class DataType : std::uint16_t {
  Boolean = 0x0001,
  Integer8 = 0x0002,
  Integer16 = 0x0003,
  Integer32 = 0x0004,
  Unsigned8 = 0x0005,
  Unsigned16 = 0x0006,
  Unsigned32 = 0x0007,
  Real32 = 0x0008,
  VisibleString = 0x0009,
  OctetString = 0x000A,
  UnicodeString = 0x000B,
  TimeOfDay = 0x000C,
  TimeDifference = 0x000D,
  Domain = 0x000F,
  Integer24 = 0x0010,
  Real64 = 0x0011,
  Integer40 = 0x0012,
  Integer48 = 0x0013,
  Integer56 = 0x0014,
  Integer64 = 0x0015,
  Unsigned24 = 0x0016,
  Unsigned40 = 0x0018,
  Unsigned48 = 0x0019,
  Unsigned56 = 0x001A,
  Unsigned64 = 0x001B,
  Guid = 0x001D,
  Byte = 0x001E,
  Word = 0x001F,
  Dword = 0x0020,
  PdoMapping = 0x0021,
  Identity = 0x0023,
  CommandPar = 0x0025,
  PdoParameter = 0x0027,
  Enum = 0x0028,
  SmSynchronisation = 0x0029,
  Record = 0x002A,
  BackupParameter = 0x002B,
  BitArr8 = 0x002D,
  BitArr16 = 0x002E,
  BitArr32 = 0x002F,
  Bit1 = 0x0030,
  Bit2 = 0x0031,
  Bit3 = 0x0032,
  Bit4 = 0x0033,
  Bit5 = 0x0034,
  Bit6 = 0x0035,
  Bit7 = 0x0036,
  Bit8 = 0x0037,
  ErrorSetting = 0x0281,
  DiagnosisHistory = 0x0282,
};

// Fixed size in bits of a basic type; 0 for the variable-length ones
// (strings, octet strings, domain) and for structured types.
constexpr std::uint16_t fixed_bit_size(DataType t) noexcept {
  switch (t) {
    case DataType::Boolean: return 1;
    case DataType::Integer8: case DataType::Unsigned8: case DataType::Byte:
    case DataType::BitArr8: return 8;
    case DataType::Integer16: case DataType::Unsigned16: case DataType::Word:
    case DataType::BitArr16: return 16;
    case DataType::Integer24: case DataType::Unsigned24: return 24;
    case DataType::Integer32: case DataType::Unsigned32: case DataType::Real32:
    case DataType::Dword: case DataType::BitArr32: return 32;
    case DataType::Integer40: case DataType::Unsigned40: return 40;
    case DataType::Integer48: case DataType::Unsigned48: case DataType::TimeOfDay:
    case DataType::TimeDifference: return 48;
    case DataType::Integer56: case DataType::Unsigned56: return 56;
    case DataType::Integer64: case DataType::Unsigned64: case DataType::Real64: return 64;
    case DataType::Guid: return 128;
    case DataType::Bit1: return 1;
    case DataType::Bit2: return 2;
    case DataType::Bit3: return 3;
    case DataType::Bit4: return 4;
    case DataType::Bit5: return 5;
    case DataType::Bit6: return 6;
    case DataType::Bit7: return 7;
    case DataType::Bit8: return 8;
    default: return 0;
  }
}

constexpr bool is_signed(DataType t) noexcept {
  switch (t) {
    case DataType::Integer8: case DataType::Integer16: case DataType::Integer24:
    case DataType::Integer32: case DataType::Integer40: case DataType::Integer48:
    case DataType::Integer56: case DataType::Integer64: return true;
    default: return false;
  }
}

constexpr bool is_real(DataType t) noexcept {
  return t == DataType::Real32 || t == DataType::Real64;
}

constexpr bool is_string(DataType t) noexcept {
  return t == DataType::VisibleString || t == DataType::OctetString ||
         t == DataType::UnicodeString || t == DataType::Domain;
}

// Spec name as written in device files and in CiA 301 ("UNSIGNED16", "BIT3").
std::string_view canopen_name(DataType t) noexcept;
std::optional<DataType> from_canopen_name(std::string_view name) noexcept;

// IEC 61131 name as the ESI uses it ("UINT", "DINT", "BIT3"); strings and
// octet strings get their length from the caller ("STRING(12)").
std::string_view esi_base_name(DataType t) noexcept;
std::optional<DataType> from_esi_base_name(std::string_view name) noexcept;

}  // namespace ecat::od
