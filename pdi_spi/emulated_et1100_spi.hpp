// An ET1100/ET1200 SPI slave PDI in front of esc::Esc (framing:
// pdi_spi/et1100_spi_registers.hpp). The address phase returns the AL event
// request 0x0220.. on MISO, reads take their length from the read
// termination byte, writes go to the ESC as they come; the IRQ pin is the
// ESC's AL event request & mask.
#pragma once

#include <span>

#include "esc/esc.hpp"
#include "pdi_spi/emulated_chip.hpp"

namespace ecat::pdi_spi {

class EmulatedEt1100Spi final : public EmulatedChip {
 public:
  explicit EmulatedEt1100Spi(esc::Esc& esc) noexcept : esc_(esc) {}
  bool transfer(std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx) noexcept override;
  bool irq_pin() const noexcept override { return esc_.irq(); }

 private:
  esc::Esc& esc_;
};

}  // namespace ecat::pdi_spi
