#include "apps/ecat-master/capture_read.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "apps/ecat-master/error_text.hpp"
#include "common/le.hpp"
#include "esi/sii_layout.hpp"
#include "master/coe_client.hpp"
#include "od/access.hpp"

namespace ecat::app {
namespace {

constexpr std::uint16_t kEscInfoRegister = 0x0000;
constexpr std::size_t kSiiReadBuffer = 8;  // one SII read delivers 4 or 8 bytes
constexpr std::size_t kBytesPerWord = 2;
constexpr std::size_t kSizeWordByte = esi::sii::kWordSize * kBytesPerWord;
// ETG.1020 10F8h Actual Time Stamp: the slave's current time, read by a
// master to age the diagnosis messages of 10F3h.
constexpr std::uint16_t kActualTimeStamp = 0x10F8;

// Ask for no unit/default/min/max with Get Entry Description: the values
// come from uploads (the current ones, which a twin takes as its defaults).
constexpr std::uint8_t kValueInfoNone = 0x00;

std::size_t eeprom_bytes(const std::vector<std::uint8_t>& fixed_area) {
  if (fixed_area.size() < kSizeWordByte + kBytesPerWord) return fixed_area.size();
  return (std::size_t{load_le<std::uint16_t>(fixed_area.data() + kSizeWordByte)} + 1) * esi::sii::kBytesPerSizeUnit;
}

}  // namespace

Expected<void, std::string> read_slave_memory(master::Master& master, std::size_t slave, esi::CaptureInput& in) {
  const master::SlaveInfo& s = master.slave(slave);
  if (auto ok = master.fprd(s.station_address, kEscInfoRegister, in.esc_info); !ok) {
    return fail(fmt::format("ESC registers 0x0000-0x000F: {}", error_text(ok.error())));
  }
  // The scan's image ends at the END category; the EEPROM goes on (0xFF
  // fill, vendor data): read every byte the size word announces.
  in.sii.clear();
  std::array<std::uint8_t, kSiiReadBuffer> buf{};
  std::size_t total = esi::sii::kFixedAreaBytes;
  while (in.sii.size() < total) {
    const auto word = static_cast<std::uint16_t>(in.sii.size() / kBytesPerWord);
    auto n = master.sii_read(s.station_address, word, buf);
    if (!n) return fail(fmt::format("SII word 0x{:04X}: {}", word, error_text(n.error())));
    const std::size_t take = std::min(*n, total - in.sii.size());
    in.sii.insert(in.sii.end(), buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(take));
    if (in.sii.size() == esi::sii::kFixedAreaBytes) {
      total = std::clamp(eeprom_bytes(in.sii), total, esi::kCaptureMaxSiiBytes);
    }
  }
  return {};
}

void read_dictionary(master::Master& master, std::size_t slave, esi::CaptureInput& in, std::vector<std::string>& notes) {
  master::CoeClient coe(master, slave);
  auto list = coe.od_list();
  if (!list) {
    notes.push_back(fmt::format("SDO information: OD list failed ({}); dictionary not captured", error_text(list.error())));
    return;
  }
  in.dictionary_read = true;
  std::vector<std::uint16_t> indices = *list;
  std::sort(indices.begin(), indices.end());
  indices.erase(std::unique(indices.begin(), indices.end()), indices.end());
  for (std::uint16_t index : indices) {
    auto od = coe.object_description(index);
    if (!od) {
      notes.push_back(fmt::format("{:04X}h: object description failed ({}); object left out", index, error_text(od.error())));
      continue;
    }
    esi::CapturedObject obj{index, od->data_type, od->max_subindex, od->object_code, od->name, {}};
    for (unsigned sub = 0; sub <= od->max_subindex; ++sub) {
      const auto si = static_cast<std::uint8_t>(sub);
      auto ed = coe.entry_description(index, si, kValueInfoNone);
      if (!ed) {
        // RECORDs may skip subindices; a described-but-absent one is no news.
        if (!(ed.error().from_slave && ed.error().code == master::SdoAbortCode::SubindexNotFound)) {
          notes.push_back(fmt::format("{:04X}h:{:02X}: entry description failed ({}); entry left out", index, sub,
                                      error_text(ed.error())));
        }
        continue;
      }
      if (ed->index != index || ed->subindex != si) {
        notes.push_back(fmt::format("{:04X}h:{:02X}: entry description answered for {:04X}h:{:02X}; entry left out",
                                    index, sub, ed->index, ed->subindex));
        continue;
      }
      esi::CapturedEntry e{si, ed->data_type, ed->bit_length, ed->access, ed->name, std::nullopt};
      if (index == kActualTimeStamp) {
        // The slave's clock (ETG.1020): a value read now is no default, and a
        // twin of the twin would differ from its original in it. Default 0,
        // no note: every device with 10F3h has it (docs/twins.md).
      } else if ((ed->access & od::Access::kReadPreOp) != 0) {
        auto v = coe.upload(index, si);
        if (v) {
          e.value = std::move(*v);
        } else {
          notes.push_back(fmt::format("{:04X}h:{:02X}: upload failed ({}); default 0", index, sub, error_text(v.error())));
        }
      } else if ((ed->access & od::Access::kReadAll) != 0) {
        notes.push_back(fmt::format("{:04X}h:{:02X}: not readable in PreOp; default 0", index, sub));
      }
      obj.entries.push_back(std::move(e));
    }
    in.objects.push_back(std::move(obj));
  }
}

}  // namespace ecat::app
