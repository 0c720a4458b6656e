// Objects of a slave read and written from the device's side (issue 26 item
// 1): straight in the CoE object store, not through the mailbox, so a test
// sets what the device would set itself - a digital input, an analog value,
// an encoder position, a temperature. The value is checked against the
// entry's type, length and the dictionary's minimum and maximum; access
// rights are the master's view (SDO) and do not apply, except that a
// constant entry is never written (docs/control.md "Objects").
//
// Values in JSON: numbers for integer, real and bit types, true/false for
// BOOLEAN, a string for VISIBLE_STRING, lowercase hex of the bytes for every
// other type (OCTET_STRING, DOMAIN, ...); {"hex": "..."} writes raw
// little-endian bytes of any type.
#pragma once

#include <cstdint>
#include <string_view>

#include <nlohmann/json.hpp>

#include "common/expected.hpp"
#include "control/control_error.hpp"

namespace ecat::od {
struct DeviceDescription;
struct PdoEntry;
}  // namespace ecat::od
namespace ecat::coe {
class ObjectStore;
}

namespace ecat::control {

// {"index", "subindex", "name", "type", "value", "hex"} of one entry.
Expected<nlohmann::json, ControlError> read_object(const coe::ObjectStore& store, std::uint16_t index,
                                                   std::uint8_t subindex);
// Writes `value`; returns what read_object then reads. Nothing changes on an error.
Expected<nlohmann::json, ControlError> write_object(coe::ObjectStore& store, std::uint16_t index,
                                                    std::uint8_t subindex, const nlohmann::json& value);

// The process-data entry named `name` in the device's PDOs ("Statusword",
// or "PDO name/entry name" when entry names repeat), its direction in `rx`.
struct NamedPdoEntry {
  const od::PdoEntry* entry = nullptr;
  bool rx = false;  // RxPDO (master -> slave) when true
  std::uint16_t pdo = 0;
};
Expected<NamedPdoEntry, ControlError> find_pdo_entry(const od::DeviceDescription& device, std::string_view name);
// Every named entry of every PDO, {"pdo", "direction", "name", "index", "subindex", "type", "value"}.
nlohmann::json list_pdo_entries(const od::DeviceDescription& device, const coe::ObjectStore& store);

}  // namespace ecat::control
