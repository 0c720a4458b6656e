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

namespace ecat::esc {

void Esc::poke_registers(std::uint16_t address, std::span<const std::uint8_t> bytes) noexcept {
  touch();
  ++address_epoch_;  // any register, the addressing ones too
  const std::size_t end = std::min<std::size_t>(std::size_t{address} + bytes.size(), kRegisterEnd);
  for (std::size_t a = address; a < end; ++a) mem_[a] = bytes[a - address];
  // What the ESC keeps of its registers: the watchdog timeouts, whether
  // 0x0440 and DL status show the running watchdogs (the next trigger
  // writes them again), the ECAT event mask.
  watchdog_times_written();
  watchdogs_.set_status_shown(false, false);
  ecat_event_mask_written();
}

}  // namespace ecat::esc
