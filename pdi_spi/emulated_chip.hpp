// The silicon side of an SPI PDI, emulated over esc::Esc: it answers each
// transaction byte-exactly as the chip's data sheet describes, so a backend
// (and the whole firmware above it) runs over the same framing it would
// see on a real chip, while a master drives the ESC's EtherCAT side. A
// frame that breaks the framing rules is answered as the chip would (or
// with zeros where the chip's answer is undefined) and counted in
// violations(), which tests expect to stay 0.
#pragma once

#include <cstdint>

#include "pdi_spi/spi_bus.hpp"

namespace ecat::pdi_spi {

class EmulatedChip : public SpiBus {
 public:
  // The chip's interrupt output to the host, asserted (whatever polarity
  // the pin is configured for).
  virtual bool irq_pin() const noexcept = 0;
  std::uint64_t violations() const noexcept { return violations_; }
  std::uint64_t transactions() const noexcept { return transactions_; }

 protected:
  void violation() noexcept { ++violations_; }
  void count() noexcept { ++transactions_; }

 private:
  std::uint64_t violations_ = 0;
  std::uint64_t transactions_ = 0;
};

}  // namespace ecat::pdi_spi
