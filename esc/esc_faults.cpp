// Esc members for fault injection (slave::FaultCatalogue, docs/faults.md):
// changes a test makes to the silicon's own state, each shown afterwards
// in the registers as the real part shows that state.
#include "esc/esc.hpp"

namespace ecat::esc {

std::optional<std::uint8_t> Esc::patch_eeprom_and_reload(std::size_t at, std::uint8_t value) {
  if (at >= config_.sii.size()) return std::nullopt;
  const std::uint8_t old = config_.sii[at];
  config_.sii.mutable_data()[at] = value;  // copy-on-write; no sii_write_back
  touch();
  load_eeprom(false);
  update_dl_status();  // bit 0 follows the checksum
  return old;
}

void Esc::set_sii_stuck(bool stuck, Nanoseconds now) noexcept {
  touch();
  sii_.set_stuck(stuck, now);
  refresh_timers();
}

}  // namespace ecat::esc
