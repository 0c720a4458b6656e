// PDO mapping entries typed as the objects they map (docs/twins.md, "Import
// policy"). A PDO mapping object's subindices 1..n are UNSIGNED32 (CiA 301
// §7.5.2.36, ETG.1000.6 §5.6.7.4.7: index 16 bits, subindex 8, bit length
// 8), whatever they map. Elmo Gold's ESI types them by the mapped object
// instead (DT1600 sub 3 "Controlword" as UINT, 16 bits; DT1606 sub 5
// "Torque Offset" as INT): taken as written, 1600h:03 is 2 bytes, the SII's
// mapping 6040:00/16 (0x60400010) no longer fits it and a master's upload
// of 1600h:03 returns 2 bytes where it reads 4. The real drive answers 4
// bytes of mapping, so the twin's entries are UNSIGNED32, one warning per
// object naming the entries and the types the file gave them.
#include <vector>

#include <fmt/format.h>

#include "esi/esi_reader_context.hpp"

namespace ecat::esi {
namespace {

constexpr std::uint16_t kRxMappingFirst = 0x1600, kRxMappingLast = 0x17FF;
constexpr std::uint16_t kTxMappingFirst = 0x1A00, kTxMappingLast = 0x1BFF;
constexpr std::uint16_t kMappingEntryBits = 32;
constexpr std::size_t kMappingEntryBytes = kMappingEntryBits / 8;

bool mapping_object(std::uint16_t index) {
  return (index >= kRxMappingFirst && index <= kRxMappingLast) || (index >= kTxMappingFirst && index <= kTxMappingLast);
}

}  // namespace

void repair_mapping_entry_types(const EsiContext& ctx, od::DeviceDescription& d) {
  std::vector<std::uint16_t> indices;
  for (const od::Object& o : d.dictionary.objects()) {
    if (mapping_object(o.index) && o.code != od::ObjectCode::Var) indices.push_back(o.index);
  }
  for (std::uint16_t index : indices) {
    od::Object& o = *d.dictionary.find(index);
    std::string retyped;
    SourcePos line = o.source_line;
    bool at_entry = false;  // line is the first retyped entry's (a position, not a line: one-line files)
    for (od::Entry& e : o.entries) {
      if (e.subindex == 0) continue;
      if (e.type == od::DataType::Unsigned32 && e.bit_length == kMappingEntryBits) continue;
      retyped += fmt::format("{}{:02X} ({}, {} bits)", retyped.empty() ? "" : ", ", e.subindex,
                             od::canopen_name(e.type), e.bit_length);
      if (!at_entry && e.source_line) {
        line = e.source_line;
        at_entry = true;
      }
      e.type = od::DataType::Unsigned32;
      e.bit_length = kMappingEntryBits;
      // The value as written, zero-extended: the mapping repair that follows
      // sets it from the PDO where the PDO says otherwise.
      e.default_value.resize(kMappingEntryBytes, 0);
      e.min_value.clear();
      e.max_value.clear();
    }
    if (retyped.empty()) continue;
    if (o.code == od::ObjectCode::Array) o.type = od::DataType::Unsigned32;
    ctx.warn_at("SubItem", line,
                fmt::format("{:04X}h (PDO mapping) entries {} are typed as the objects they map; a mapping entry is "
                            "UNSIGNED32, so are the twin's",
                            o.index, retyped));
  }
}

}  // namespace ecat::esi
