#include "pdi_spi/spidev_bus.hpp"

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <fmt/format.h>

namespace ecat::pdi_spi {

spi_ioc_transfer make_spi_transfer(std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx,
                                   const SpidevOptions& options) noexcept {
  spi_ioc_transfer t{};
  t.tx_buf = reinterpret_cast<std::uintptr_t>(tx.data());
  t.rx_buf = reinterpret_cast<std::uintptr_t>(rx.data());
  t.len = static_cast<std::uint32_t>(tx.size());
  t.speed_hz = options.speed_hz;
  t.bits_per_word = options.bits_per_word;
  t.delay_usecs = 0;
  t.cs_change = 0;  // the message is one transfer: CS is released after it
  return t;
}

Expected<std::unique_ptr<SpidevBus>, std::string> SpidevBus::open(const SpidevOptions& options) {
  const int fd = ::open(options.device.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) return fail(fmt::format("{}: cannot open: {}", options.device, std::strerror(errno)));
  auto step = [&](unsigned long request, const void* value, const char* what) -> std::string {
    if (::ioctl(fd, request, value) == 0) return {};
    return fmt::format("{}: {}: {}", options.device, what, std::strerror(errno));
  };
  const std::uint8_t mode = options.mode;
  const std::uint8_t bits = options.bits_per_word;
  const std::uint32_t speed = options.speed_hz;
  for (const std::string& error : {step(SPI_IOC_WR_MODE, &mode, "setting the SPI mode"),
                                   step(SPI_IOC_WR_BITS_PER_WORD, &bits, "setting bits per word"),
                                   step(SPI_IOC_WR_MAX_SPEED_HZ, &speed, "setting the clock")}) {
    if (!error.empty()) {
      ::close(fd);
      return fail(error);
    }
  }
  return std::unique_ptr<SpidevBus>(new SpidevBus(fd, options));
}

SpidevBus::~SpidevBus() { ::close(fd_); }

bool SpidevBus::transfer(std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx) noexcept {
  spi_ioc_transfer t = make_spi_transfer(tx, rx, options_);
  if (::ioctl(fd_, SPI_IOC_MESSAGE(1), &t) < 0) {
    errno_ = errno;
    return false;
  }
  return true;
}

}  // namespace ecat::pdi_spi
