#include "esi/cpp_writer.hpp"

#include <fmt/format.h>

#include <string>
#include <vector>

namespace ecat::esi {
namespace {

constexpr std::uint8_t kNoSm = 0xFF;
constexpr std::size_t kValuesPerLine = 16;

// A C++ string literal; everything outside printable ASCII as a 3-digit octal
// escape (which cannot swallow a following digit the way \x can).
std::string literal(std::string_view s) {
  std::string out = "\"";
  for (unsigned char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20 || c >= 0x7F || c == '?') {  // '?' avoids trigraph warnings
      out += fmt::format("\\{:03o}", c);
    } else {
      out += static_cast<char>(c);
    }
  }
  return out + "\"";
}

// `std::array<T, N> name{{ rows }}` (or `{}` for no rows).
void table(std::string& out, std::string_view type, std::string_view name,
           const std::vector<std::string>& rows) {
  out += fmt::format("inline constexpr std::array<{}, {}> {}{{", type, rows.size(), name);
  if (rows.empty()) {
    out += "};\n\n";
    return;
  }
  out += "{\n";
  for (const auto& r : rows) out += "    " + r + ",\n";
  out += "}};\n\n";
}

class ValuePool {
 public:
  // Offset and size of `v` in the pool (empty values take no bytes).
  std::string add(const od::Value& v) {
    const std::size_t offset = bytes_.size();
    bytes_.insert(bytes_.end(), v.begin(), v.end());
    return fmt::format("{}, {}", offset, v.size());
  }
  void write(std::string& out) const {
    out += fmt::format("inline constexpr std::array<std::uint8_t, {}> kValues{{", bytes_.size());
    if (bytes_.empty()) {
      out += "};\n\n";
      return;
    }
    out += "{";
    for (std::size_t i = 0; i < bytes_.size(); ++i) {
      out += (i % kValuesPerLine == 0) ? "\n    " : " ";
      out += fmt::format("0x{:02X},", bytes_[i]);
    }
    out += "\n}};\n\n";
  }

 private:
  std::vector<std::uint8_t> bytes_;
};

constexpr const char* kTypes = R"(// Values are little-endian bytes as on the wire, found in kValues at
// [offset, offset + size); size 0 = not given.
struct ValueRef {
  std::uint32_t offset;
  std::uint16_t size;
};

struct Identity {
  std::uint32_t vendor_id;
  std::uint32_t product_code;
  std::uint32_t revision;
  std::uint32_t serial;
  std::uint32_t device_type;  // object 1000h
  const char* name;
  const char* type_name;
};

struct SyncManager {
  std::uint16_t start_address;
  std::uint16_t default_size;  // 0 for process data: from the assigned PDOs
  std::uint8_t control;        // register 0x0804
  std::uint8_t type;           // 0 unused, 1 MBoxOut, 2 MBoxIn, 3 Outputs, 4 Inputs
  bool enable;
};

struct Entry {
  std::uint8_t subindex;
  std::uint16_t data_type;   // CoE data type index (ETG.1000.6 Table 64)
  std::uint16_t bit_length;
  std::uint16_t access;      // SDO information ObjAccess bits
  ValueRef default_value;
  ValueRef min_value;
  ValueRef max_value;
  const char* name;
};

struct Object {
  std::uint16_t index;
  std::uint8_t object_code;  // 7 VAR, 8 ARRAY, 9 RECORD
  std::uint16_t data_type;
  std::uint16_t first_entry;  // into kEntries
  std::uint16_t entry_count;
  const char* name;
};

struct PdoEntry {
  std::uint16_t index;  // 0 with subindex 0: a gap
  std::uint8_t subindex;
  std::uint8_t bit_length;
};

struct Pdo {
  std::uint16_t index;
  std::uint8_t sm;  // default SM, 0xFF = not assigned by default
  bool fixed;
  bool mandatory;
  std::uint16_t first_entry;  // into kPdoEntries
  std::uint16_t entry_count;
  const char* name;
};

)";

constexpr const char* kFind = R"(// The object with `index` (binary search: kObjects is sorted), or nullptr.
constexpr const Object* find_object(std::uint16_t index) noexcept {
  std::size_t lo = 0;
  std::size_t hi = kObjects.size();
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (kObjects[mid].index == index) return &kObjects[mid];
    if (kObjects[mid].index < index) {
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  return nullptr;
}

// The entry `subindex` of `object`, or nullptr.
constexpr const Entry* find_entry(const Object& object, std::uint8_t subindex) noexcept {
  for (std::size_t i = object.first_entry; i < std::size_t{object.first_entry} + object.entry_count; ++i) {
    if (kEntries[i].subindex == subindex) return &kEntries[i];
  }
  return nullptr;
}
)";

void pdo_rows(const std::vector<od::Pdo>& pdos, std::vector<std::string>& rows,
              std::vector<std::string>& entries) {
  for (const auto& p : pdos) {
    rows.push_back(fmt::format("Pdo{{0x{:04X}, 0x{:02X}, {}, {}, {}, {}, {}}}", p.index,
                               p.sm ? *p.sm : kNoSm, p.fixed, p.mandatory, entries.size(),
                               p.entries.size(), literal(p.name)));
    for (const auto& e : p.entries) {
      entries.push_back(fmt::format("PdoEntry{{0x{:04X}, {}, {}}}", e.index, e.subindex, e.bit_length));
    }
  }
}

}  // namespace

std::string write_cpp_tables(const od::DeviceDescription& d, std::string_view ns) {
  const auto& id = d.identity;
  std::string out;
  out += fmt::format("// Generated by ecat-esigen (ecatslave) from the device description of {}.\n",
                     id.name.empty() ? std::string("a device") : id.name);
  out += "// Do not edit by hand: change the device file and generate again.\n";
  out += "#pragma once\n\n#include <array>\n#include <cstddef>\n#include <cstdint>\n\n";
  out += fmt::format("namespace {} {{\n\n", ns);
  out += kTypes;
  out += fmt::format("inline constexpr Identity kIdentity{{0x{:08X}, 0x{:08X}, 0x{:08X}, 0x{:08X}, "
                     "0x{:08X}, {}, {}}};\n\n",
                     id.vendor_id, id.product_code, id.revision, id.serial, id.device_type,
                     literal(id.name), literal(id.type_name));
  std::vector<std::string> rows;
  for (const auto& sm : d.sync_managers) {
    rows.push_back(fmt::format("SyncManager{{0x{:04X}, {}, 0x{:02X}, {}, {}}}", sm.start_address,
                               sm.default_size, sm.control, static_cast<int>(sm.type), sm.enable));
  }
  table(out, "SyncManager", "kSyncManagers", rows);

  ValuePool pool;
  std::vector<std::string> entries;
  std::vector<std::string> objects;
  for (const auto& o : d.dictionary.objects()) {
    objects.push_back(fmt::format("Object{{0x{:04X}, {}, 0x{:04X}, {}, {}, {}}}", o.index,
                                  static_cast<int>(o.code), static_cast<int>(o.type),
                                  entries.size(), o.entries.size(), literal(o.name)));
    for (const auto& e : o.entries) {
      const std::string def = pool.add(e.default_value);
      const std::string min = pool.add(e.min_value);
      const std::string max = pool.add(e.max_value);
      entries.push_back(fmt::format("Entry{{{}, 0x{:04X}, {}, 0x{:04X}, {{{}}}, {{{}}}, {{{}}}, {}}}",
                                    e.subindex, static_cast<int>(e.type), e.bit_length,
                                    e.access.bits, def, min, max, literal(e.name)));
    }
  }
  pool.write(out);
  table(out, "Entry", "kEntries", entries);
  table(out, "Object", "kObjects", objects);

  std::vector<std::string> pdo_entries;
  std::vector<std::string> rx;
  std::vector<std::string> tx;
  pdo_rows(d.rx_pdos, rx, pdo_entries);
  pdo_rows(d.tx_pdos, tx, pdo_entries);
  table(out, "PdoEntry", "kPdoEntries", pdo_entries);
  table(out, "Pdo", "kRxPdos", rx);
  table(out, "Pdo", "kTxPdos", tx);
  out += kFind;
  out += fmt::format("\n}}  // namespace {}\n", ns);
  return out;
}

}  // namespace ecat::esi
