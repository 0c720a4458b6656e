// SpiBus on Linux spidev (Documentation/spi/spidev): one SPI_IOC_MESSAGE(1)
// ioctl per transaction, chip select held for the whole transfer. Mode,
// clock and word size are set once when the device is opened. Not run
// against hardware in this project's CI (docs/real-esc.md).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include <linux/spi/spidev.h>

#include "common/expected.hpp"
#include "pdi_spi/spi_bus.hpp"

namespace ecat::pdi_spi {

struct SpidevOptions {
  std::string device;                // /dev/spidevB.C
  std::uint8_t mode = 0;             // SPI mode 0-3 (CPOL/CPHA); LAN9252: 0 or 3; ET1100: per SII 0x0150
  std::uint32_t speed_hz = 10'000'000;
  std::uint8_t bits_per_word = 8;
};

// The ioctl argument for one full-duplex transaction (tested without
// hardware): both buffers, their length, the clock and word size; chip
// select released at the end, no delay.
spi_ioc_transfer make_spi_transfer(std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx,
                                   const SpidevOptions& options) noexcept;

class SpidevBus final : public SpiBus {
 public:
  // Opens the device and sets mode, word size and clock; a message naming
  // the device and the failing step otherwise.
  static Expected<std::unique_ptr<SpidevBus>, std::string> open(const SpidevOptions& options);
  ~SpidevBus() override;
  SpidevBus(const SpidevBus&) = delete;
  SpidevBus& operator=(const SpidevBus&) = delete;

  bool transfer(std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx) noexcept override;
  // errno of the last failed transfer.
  int last_errno() const noexcept { return errno_; }

 private:
  SpidevBus(int fd, SpidevOptions options) noexcept : fd_(fd), options_(std::move(options)) {}
  int fd_;
  SpidevOptions options_;
  int errno_ = 0;
};

}  // namespace ecat::pdi_spi
