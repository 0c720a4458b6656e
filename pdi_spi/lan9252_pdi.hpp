// esc::Pdi over a Microchip LAN9252 on SPI (data sheet DS00001909). The
// ESC core is not directly addressable from the host: registers below
// 0x1000 go through the indirect CSR interface (ECAT_CSR_DATA/ECAT_CSR_CMD,
// 1, 2 or 4 naturally aligned bytes per command), process RAM through the
// PRAM read/write FIFOs (ECAT_PRAM_RD/WR_ADDR_LEN, _CMD, the FIFO data
// ports), one command per access so a whole SM buffer is one burst.
// docs/real-esc.md gives every sequence with its bytes and sources.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "pdi_spi/spi_pdi.hpp"

namespace ecat::pdi_spi {

struct Lan9252Options {
  // FAST READ (0Bh, one dummy byte) instead of READ (03h) for every read.
  bool fast_read = false;
  // PRAM address/length and command written in one 8-byte burst
  // (ECAT_PRAM_xx_ADDR_LEN and _CMD are adjacent; relies on the SPI address
  // auto-increment) instead of two writes.
  bool burst_setup = false;
  // Read ECAT_CSR_DATA right after the read command without polling
  // CSR_BUSY (what Microchip's own driver does, with FAST READ); off: poll
  // until CSR_BUSY clears, as SOES does.
  bool skip_csr_poll = false;
  // Polls of a busy/available bit before the access counts as failed.
  unsigned max_polls = 100000;
};

class Lan9252Pdi final : public SpiPdi {
 public:
  static constexpr std::size_t kMaxBurst = 2048;  // data bytes per transaction

  explicit Lan9252Pdi(SpiBus& bus, Lan9252Options options = {}) noexcept : SpiPdi(bus), options_(options) {}

  // Bring-up: BYTE_TEST shows the pattern (the SPI works and the byte order
  // is right), HW_CFG READY, then the IRQ pin (enabled, push-pull, active
  // low) with ECAT_INT as its only source. False with error() on failure.
  bool init() noexcept;

  void read(std::uint16_t address, std::span<std::uint8_t> out) noexcept override;
  void write(std::uint16_t address, std::span<const std::uint8_t> in) noexcept override;

  // The host-side (non-ESC) system registers: one 4-byte SPI access.
  std::uint32_t read_system(std::uint16_t address) noexcept;
  void write_system(std::uint16_t address, std::uint32_t value) noexcept;

 private:
  void csr_read(std::uint16_t address, std::span<std::uint8_t> out) noexcept;
  void csr_write(std::uint16_t address, std::span<const std::uint8_t> in) noexcept;
  void pram_read(std::uint16_t address, std::span<std::uint8_t> out) noexcept;
  void pram_write(std::uint16_t address, std::span<const std::uint8_t> in) noexcept;
  void pram_start(std::uint16_t addr_len_reg, std::uint16_t address, std::size_t length) noexcept;
  // Reads `reg` until (value & mask) == want; false after max_polls.
  bool poll(std::uint16_t reg, std::uint32_t mask, std::uint32_t want) noexcept;
  // One READ/FAST READ of `out.size()` bytes at `address`.
  bool spi_read(std::uint16_t address, std::span<std::uint8_t> out) noexcept;
  // One WRITE of `in` at `address`.
  bool spi_write(std::uint16_t address, std::span<const std::uint8_t> in) noexcept;

  Lan9252Options options_;
  std::array<std::uint8_t, kMaxBurst + 8> tx_{};
  std::array<std::uint8_t, kMaxBurst + 8> rx_{};
};

// The CSR command size for an access of `remaining` bytes at `address`:
// 4 when DWORD-aligned with 4 left, 2 when WORD-aligned with 2 left, else 1
// (CSR accesses are naturally aligned, DS00001909 CSR address/size table).
std::size_t lan9252_csr_size(std::uint16_t address, std::size_t remaining) noexcept;

}  // namespace ecat::pdi_spi
