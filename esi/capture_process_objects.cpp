#include "esi/capture_process_objects.hpp"

#include <fmt/format.h>

#include "od/type_of_bits.hpp"

namespace ecat::esi {
namespace {

constexpr std::uint16_t kBitsPerByte = 8;

od::Entry process_entry(const od::PdoEntry& pe, bool rx) {
  od::Entry e;
  e.subindex = pe.subindex;
  e.name = pe.name.empty() ? fmt::format("SubIndex {:03}", pe.subindex) : pe.name;
  e.type = type_of_bits(pe.bit_length).value_or(pe.type);
  e.bit_length = pe.bit_length;
  e.access.bits = static_cast<std::uint16_t>(rx ? (od::Access::kRw | od::Access::kRxPdoMappable)
                                                : (od::Access::kRo | od::Access::kTxPdoMappable));
  e.default_value.assign((pe.bit_length + kBitsPerByte - 1) / kBitsPerByte, 0);
  return e;
}

od::Entry count_entry(std::uint8_t highest) {
  od::Entry e;
  e.subindex = 0;
  e.name = "Number of entries";
  e.type = od::DataType::Unsigned8;
  e.bit_length = kBitsPerByte;
  e.default_value = {highest};
  return e;
}

}  // namespace

std::optional<od::DataType> type_of_bits(std::uint16_t bits) noexcept { return od::unsigned_type_of_bits(bits); }

void add_process_objects(const od::Pdo& pdo, od::DeviceDescription& d, std::vector<std::string>& notes) {
  for (const od::PdoEntry& pe : pdo.entries) {
    if (pe.index == 0) continue;  // a gap
    if (const od::Entry* have = d.dictionary.find(pe.index, pe.subindex)) {
      if (have->bit_length != pe.bit_length) {
        notes.push_back(fmt::format("PDO {:04X}h: entry {:04X}h:{:02X} has {} bits, the object {}", pdo.index,
                                    pe.index, pe.subindex, pe.bit_length, have->bit_length));
      }
      continue;
    }
    if (!type_of_bits(pe.bit_length) && od::fixed_bit_size(pe.type) != pe.bit_length) {
      notes.push_back(fmt::format("PDO {:04X}h: entry {:04X}h:{:02X} of {} bits has no type of that size; left out",
                                  pdo.index, pe.index, pe.subindex, pe.bit_length));
      continue;
    }
    od::Object* o = d.dictionary.find(pe.index);
    const od::Entry e = process_entry(pe, pdo.is_rx());
    if (o == nullptr) {
      od::Object obj;
      obj.index = pe.index;
      obj.name = pe.name.empty() ? fmt::format("Object {:04X}h", pe.index) : pe.name;
      if (pe.subindex == 0) {
        obj.code = od::ObjectCode::Var;
        obj.type = e.type;
        obj.entries.push_back(e);
      } else {
        obj.code = od::ObjectCode::Record;
        obj.type = od::DataType::Record;
        obj.entries.push_back(count_entry(pe.subindex));
        obj.entries.push_back(e);
      }
      if (auto ok = d.dictionary.put(std::move(obj)); !ok) {
        notes.push_back(fmt::format("PDO {:04X}h: object {:04X}h not created: {}", pdo.index, pe.index, ok.error()));
        continue;
      }
    } else if (o->code == od::ObjectCode::Record && pe.subindex != 0) {
      auto at = o->entries.begin();
      while (at != o->entries.end() && at->subindex < pe.subindex) ++at;
      o->entries.insert(at, e);
      if (od::Entry* count = o->find(0)) count->default_value = {o->max_subindex()};
    } else {
      notes.push_back(fmt::format("PDO {:04X}h: entry {:04X}h:{:02X} does not fit object {:04X}h; left out",
                                  pdo.index, pe.index, pe.subindex, pe.index));
      continue;
    }
    notes.push_back(fmt::format("PDO {:04X}h: {:04X}h:{:02X} has no dictionary object; created as process data "
                                "({} bits)",
                                pdo.index, pe.index, pe.subindex, pe.bit_length));
  }
}

}  // namespace ecat::esi
