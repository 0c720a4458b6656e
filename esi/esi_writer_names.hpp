// Spellings the ESI (ETG.2000) uses, shared by the ESI writer and reader so
// both sides agree: "#x" hex numbers, hexBinary values, IEC 61131 type names
// of entries ("UINT", "STRING(16)", "ARRAY [0..3] OF BYTE") and the
// Access/ReadRestrictions/WriteRestrictions/PdoMapping flags.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "od/access.hpp"
#include "od/object.hpp"

namespace ecat::esi {

// "#x" followed by at least `digits` upper-case hex digits ("#x1C12").
std::string esi_hex(std::uint64_t value, int digits);
// xs:hexBinary of the bytes in order ("0A00"), upper case.
std::string hex_binary(const od::Value& bytes);
// Inverse of hex_binary; nullopt on odd length or a non-hex character.
std::optional<od::Value> parse_hex_binary(std::string_view text);

// ESI type name of an entry: the basic name, or STRING(n) / UNICODE_STRING(n)
// / ARRAY [0..n-1] OF BYTE (octet strings) with n from the bit length.
std::string esi_entry_type_name(od::DataType type, std::uint16_t bit_length);

struct EsiTypeName {
  od::DataType type;
  std::uint16_t bit_length;  // 0 = the type's fixed size
};
// Inverse for the names above and the plain basic names; nullopt if unknown.
std::optional<EsiTypeName> parse_esi_type_name(std::string_view name);

// Flags/Access text and restriction attributes (ETG.2000 AccessType).
struct EsiAccess {
  std::string access;              // "ro", "rw", "wo"
  std::string read_restrictions;   // "" = readable in every state that allows SDO
  std::string write_restrictions;  // "" = writable in every state
};
EsiAccess esi_access(const od::Access& a);
// Inverse; nullopt for an unknown access or restriction word.
std::optional<std::uint16_t> parse_esi_access(std::string_view access,
                                              std::string_view read_restrictions,
                                              std::string_view write_restrictions);

// Flags/PdoMapping: "R", "T", "RT" or "" when not mappable.
std::string esi_pdo_mapping(const od::Access& a);
// Inverse (case-insensitive; "TR" = "RT"); nullopt if unknown.
std::optional<std::uint16_t> parse_esi_pdo_mapping(std::string_view text);

}  // namespace ecat::esi
