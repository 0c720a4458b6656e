// An ET1100/ET1200 SPI slave PDI in front of esc::Esc (framing:
// pdi_spi/et1100_spi_registers.hpp). The address phase returns the AL event
// request 0x0220.. on MISO, reads take their length from the read
// termination byte, writes go to the ESC as they come; the IRQ pin is the
// ESC's AL event request & mask. An access with an SPI interface error
// counts in the ESC's PDI error counter 0x030D with its reason in the PDI
// error code 0x030E (Section II §2.9.4/§2.9.5.1; docs/real-esc.md "PDI
// error counter"): a clock count that is not whole bytes, a read without
// termination byte, bytes clocked after the termination.
#pragma once

#include <cstddef>
#include <span>

#include "esc/esc.hpp"
#include "pdi_spi/emulated_chip.hpp"

namespace ecat::pdi_spi {

class EmulatedEt1100Spi final : public EmulatedChip {
 public:
  explicit EmulatedEt1100Spi(esc::Esc& esc) noexcept : esc_(esc) {}
  // One access of whole bytes (8 clocks each).
  bool transfer(std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx) noexcept override;
  // One access of `clocks` SPI clock cycles, as from a host whose SPI master
  // can release SPI_SEL inside a byte: tx and rx hold ceil(clocks / 8)
  // bytes, MSB first; of the last byte only the first clocks % 8 bits are
  // clocked (the chip never sees the rest of its MOSI bits).
  bool transfer_clocks(std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx, std::size_t clocks) noexcept;
  bool irq_pin() const noexcept override { return esc_.irq(); }

 private:
  esc::Esc& esc_;
};

}  // namespace ecat::pdi_spi
