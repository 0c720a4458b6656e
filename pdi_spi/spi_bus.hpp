// The one thing a PDI backend needs from the hardware: full-duplex SPI
// transactions. A transaction asserts chip select, clocks tx.size() bytes
// out on MOSI while the same number come in on MISO, and releases chip
// select. Porting the backends to a microcontroller means rewriting only
// this interface (and, optionally, the interrupt line).
#pragma once

#include <cstdint>
#include <span>

namespace ecat::pdi_spi {

class SpiBus {
 public:
  virtual ~SpiBus() = default;
  // One transaction; `rx` has the size of `tx`. False when the transfer
  // failed (the backend then reports the error and reads zeros).
  virtual bool transfer(std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx) noexcept = 0;
};

// What a backend moved over the bus, for the cost per application cycle
// (docs/real-esc.md): every transaction and every byte clocked.
struct SpiCounters {
  std::uint64_t transactions = 0;
  std::uint64_t bytes = 0;
};

}  // namespace ecat::pdi_spi
