// PDOs of a slave captured from its SII alone (no CoE, or no SDO
// information): the TXPDO/RXPDO categories as the default PDOs, their entries'
// objects created as process data (esi/capture_process_objects.hpp).
#include <fmt/format.h>

#include "esi/capture_model.hpp"
#include "esi/capture_process_objects.hpp"
#include "esi/sii_image.hpp"

namespace ecat::esi {
namespace {

od::Pdo pdo_from_sii(const SiiImage& img, const SiiPdo& s) {
  od::Pdo p;
  p.index = s.index;
  p.name = img.string_at(s.name_idx);
  p.fixed = (s.flags & sii::kPdoFixed) != 0;
  p.mandatory = (s.flags & sii::kPdoMandatory) != 0;
  if (s.sync_manager != sii::kPdoNoSm) p.sm = s.sync_manager;
  for (const SiiPdoEntry& se : s.entries) {
    od::PdoEntry e;
    e.index = se.index;
    e.subindex = se.subindex;
    e.bit_length = se.bit_length;
    e.name = img.string_at(se.name_idx);
    e.type = static_cast<od::DataType>(se.data_type);
    p.entries.push_back(e);
  }
  return p;
}

}  // namespace

void apply_sii_pdos(const SiiImage& img, od::DeviceDescription& d, std::vector<std::string>& notes) {
  if (d.mailbox.coe) {
    notes.push_back("dictionary: not read over SDO information; only the objects of the SII's PDO entries are "
                    "in the device file (process data, default 0)");
  }
  for (const auto* list : {&img.rx_pdos, &img.tx_pdos}) {
    for (const SiiPdo& s : *list) {
      od::Pdo p = pdo_from_sii(img, s);
      const bool rx = list == &img.rx_pdos;
      if (p.is_rx() != rx) {
        notes.push_back(fmt::format("SII: {} PDO {:04X}h outside its index range; left out", rx ? "RxPDO" : "TxPDO",
                                    p.index));
        continue;
      }
      add_process_objects(p, d, notes);
      (rx ? d.rx_pdos : d.tx_pdos).push_back(std::move(p));
    }
  }
}

}  // namespace ecat::esi
