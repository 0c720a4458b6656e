// Object dictionary model (CiA 301 §7.4, ETG.1000.6 §5.6): objects with their
// entries, as loaded from a device description or a vendor's ESI. This is the
// description, not the live values: the CoE layer keeps the values.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/source_pos.hpp"
#include "od/access.hpp"
#include "od/data_type.hpp"

namespace ecat::od {

// Object codes (CiA 301 Table 38 / ETG.1000.6 §5.6.3.5).
enum class ObjectCode : std::uint8_t { Var = 7, Array = 8, Record = 9 };

// Values are kept as the little-endian bytes that go on the wire, sized
// ceil(bit_length / 8); strings hold their characters. An empty vector means
// "not given" for min/max.
using Value = std::vector<std::uint8_t>;

struct Entry {
  std::uint8_t subindex = 0;
  std::string name;
  DataType type = DataType::Unsigned8;
  std::uint16_t bit_length = 8;  // for strings: 8 * maximum length
  Access access;
  Value default_value;
  Value min_value;
  Value max_value;
  std::string unit;
  std::string description;
  // Where the element that declared this entry is (line 0 if built in code),
  // so later checks can still point at the vendor or device file; the column
  // too where the line alone does not say (a one-line configurator export).
  SourcePos source_line;

  bool has_min() const noexcept { return !min_value.empty(); }
  bool has_max() const noexcept { return !max_value.empty(); }
};

struct Object {
  std::uint16_t index = 0;
  std::string name;
  ObjectCode code = ObjectCode::Var;
  // For a VAR: the entry's type. For ARRAY: the element type. For RECORD: the
  // structured type (DataType::Record, Identity, PdoMapping, ...).
  DataType type = DataType::Unsigned8;
  // Name of the ESI DataType that describes this object ("DT1018"); empty to
  // let the ESI writer choose one.
  std::string type_name;
  // VAR: exactly one entry with subindex 0. ARRAY/RECORD: subindex 0
  // ("number of entries", UNSIGNED8) first, then the others in ascending order;
  // gaps are allowed in a RECORD.
  std::vector<Entry> entries;
  std::string description;
  SourcePos source_line;  // as Entry::source_line

  const Entry* find(std::uint8_t subindex) const noexcept;
  Entry* find(std::uint8_t subindex) noexcept;
  // Highest subindex declared (the default of subindex 0 for ARRAY/RECORD).
  std::uint8_t max_subindex() const noexcept;
};

}  // namespace ecat::od
