// Discovers objects through SDO Information (ETG.1000.6 §5.6.3) so the SDO
// cases can find, on any device, a read-only entry, a writable one, one with
// a value range, and an index that does not exist.
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "master/conformance/suite.hpp"

namespace ecat::master::conformance {

// Object access bits of an entry description (coe-mailbox.md §7.3).
inline constexpr std::uint16_t kAccessReadPreOp = 0x0001;
inline constexpr std::uint16_t kAccessWritePreOp = 0x0008;
inline constexpr std::uint16_t kAccessWriteAny = 0x0038;
inline constexpr std::uint8_t kValueInfoRange = coe::kValueInfoMinimum | coe::kValueInfoMaximum;
inline constexpr std::uint8_t kValueInfoBasic = 0x07;
inline constexpr std::uint8_t kObjectCodeVar = 0x07;  // coe-mailbox.md §7.2

struct WalkedEntry {
  ObjectDescription object;
  EntryDescription entry;
};

// Calls `visit` for every entry of every object in the OD list (up to
// `max_objects` objects, 0 = all) with index >= `from`; stops when it returns
// true and gives that entry back.
Expected<std::optional<WalkedEntry>, SdoError> walk_od(Context& ctx, std::uint16_t from, std::uint8_t value_info,
                                                       const std::function<bool(const WalkedEntry&)>& visit);

// Bytes an entry of `data_type`/`bit_length` takes in an SDO transfer; 0 for
// variable-length types (strings, domain).
std::size_t sdo_size(std::uint16_t data_type, std::uint16_t bit_length);
bool is_integer_type(std::uint16_t data_type);
bool is_signed_type(std::uint16_t data_type);

}  // namespace ecat::master::conformance
