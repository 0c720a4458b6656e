// A LAN9252 SPI slave in front of esc::Esc (registers:
// pdi_spi/lan9252_registers.hpp). READ/FAST READ/WRITE with a 16-bit
// address; system registers latched a DWORD at a time; the indirect CSR
// interface executes a command when the byte holding CSR_BUSY is written;
// the PRAM FIFOs move whole DWORDs with the start address's byte lane. The
// emulated chip completes every command at once (busy reads 0 on the first
// poll), where silicon takes a few hundred ns - the backend polls either way.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "esc/esc.hpp"
#include "pdi_spi/emulated_chip.hpp"

namespace ecat::pdi_spi {

class EmulatedLan9252 final : public EmulatedChip {
 public:
  // Identification the emulated chip reports in ID_REV (chip ID 0x9252).
  static constexpr std::uint32_t kIdRevValue = 0x92520001;

  explicit EmulatedLan9252(esc::Esc& esc) noexcept : esc_(esc) {}
  bool transfer(std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx) noexcept override;
  // The IRQ pin: IRQ_EN and (INT_STS & INT_EN), INT_STS.ECAT_INT being the
  // ESC's AL event request & AL event mask.
  bool irq_pin() const noexcept override;

 private:
  // One PRAM direction: the DWORD stream between the FIFO port and the ESC.
  struct Pram {
    std::uint32_t addr_len = 0;
    bool active = false;
    std::size_t total = 0;     // FIFO bytes of the command (whole DWORDs)
    std::size_t position = 0;  // FIFO bytes moved so far
    std::array<std::uint8_t, 0x10000 + 8> data{};
  };

  std::uint32_t read_register(std::uint16_t dword_address) noexcept;
  void write_register_byte(std::uint16_t address, std::uint8_t value) noexcept;
  std::uint8_t fifo_pop() noexcept;
  void fifo_push(std::uint8_t value) noexcept;
  void csr_command() noexcept;
  void pram_read_start() noexcept;
  void pram_write_start() noexcept;
  std::uint32_t pram_command(const Pram& p) const noexcept;
  std::uint32_t int_status() const noexcept;

  esc::Esc& esc_;
  std::uint32_t irq_cfg_ = 0;
  std::uint32_t int_en_ = 0;
  std::uint32_t csr_data_ = 0;
  std::uint32_t csr_cmd_ = 0;
  std::uint32_t rd_cmd_ = 0;
  std::uint32_t wr_cmd_ = 0;
  Pram rd_;
  Pram wr_;
};

}  // namespace ecat::pdi_spi
