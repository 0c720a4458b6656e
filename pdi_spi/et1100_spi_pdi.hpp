// esc::Pdi over a Beckhoff ET1100/ET1200 SPI PDI: every access is one
// transaction (address/command phase + data phase), so a whole SM buffer
// is one burst, and the AL event request register comes back in the first
// bytes of every access: a read of 0x0220 starts its data phase after the
// bytes the address phase already returned (the piggyback the issue asks
// for). Framing: pdi_spi/et1100_spi_registers.hpp, docs/real-esc.md.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "pdi_spi/spi_pdi.hpp"

namespace ecat::pdi_spi {

struct Et1100SpiOptions {
  // Reads with command 3 (one wait-state byte between address and data
  // phase) so the SPI master need not pause; command 2 needs the master to
  // wait t_read between the phases, which one spidev transfer cannot do.
  bool wait_state = true;
  // Always use the 3-byte address phase (else only above 0x1FFF).
  bool three_byte_address = false;
};

class Et1100SpiPdi final : public SpiPdi {
 public:
  static constexpr std::size_t kMaxBurst = 2048;  // data bytes per transaction

  explicit Et1100SpiPdi(SpiBus& bus, Et1100SpiOptions options = {}) noexcept : SpiPdi(bus), options_(options) {}

  void read(std::uint16_t address, std::span<std::uint8_t> out) noexcept override;
  void write(std::uint16_t address, std::span<const std::uint8_t> in) noexcept override;

  // AL event request 0x0220-0x0221 as the last access returned it.
  std::uint16_t last_al_event() const noexcept { return last_al_event_; }

 private:
  // Address phase for `address`/`command` into tx_; returns its length.
  std::size_t address_phase(std::uint16_t address, std::uint8_t command) noexcept;
  // One read transaction; `out` may be empty (an address phase alone).
  // Returns how many bytes of 0x0220... the address phase carried.
  std::size_t read_once(std::uint16_t address, std::span<std::uint8_t> out, std::span<std::uint8_t> al_event) noexcept;
  void write_once(std::uint16_t address, std::span<const std::uint8_t> in) noexcept;

  Et1100SpiOptions options_;
  std::uint16_t last_al_event_ = 0;
  std::array<std::uint8_t, kMaxBurst + 4> tx_{};
  std::array<std::uint8_t, kMaxBurst + 4> rx_{};
};

}  // namespace ecat::pdi_spi
