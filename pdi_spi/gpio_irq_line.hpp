// The ESC's interrupt output on a GPIO input, through the GPIO character
// device uAPI v2 (linux/gpio.h): one line requested as an input with edge
// detection on its assertion, so the host sleeps in poll() until the chip
// raises IRQ or its own deadline comes. Not run against hardware in this
// project's CI (docs/real-esc.md).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include <linux/gpio.h>

#include "common/clock.hpp"
#include "common/expected.hpp"

namespace ecat::pdi_spi {

struct GpioLineOptions {
  std::string chip = "/dev/gpiochip0";
  std::uint32_t offset = 0;
  // The LAN9252 as the backend programs it drives IRQ active low; the
  // ET1100's polarity comes from the SII (0x0150/0x0151).
  bool active_low = true;
};

// The GPIO_V2_GET_LINE_IOCTL argument (tested without hardware): one line,
// input, ACTIVE_LOW as asked, edge detection on the logical rising edge
// (inactive to active, i.e. the IRQ being asserted), consumer "ecat-slave".
gpio_v2_line_request make_gpio_line_request(const GpioLineOptions& options) noexcept;

class GpioIrqLine {
 public:
  static Expected<std::unique_ptr<GpioIrqLine>, std::string> open(const GpioLineOptions& options);
  ~GpioIrqLine();
  GpioIrqLine(const GpioIrqLine&) = delete;
  GpioIrqLine& operator=(const GpioIrqLine&) = delete;

  // Whether the IRQ is asserted now (logical value of the line).
  bool asserted() noexcept;
  // Sleeps until an assertion edge or `timeout`; drains the edge events.
  // True when an edge came.
  bool wait(Nanoseconds timeout) noexcept;

 private:
  explicit GpioIrqLine(int fd) noexcept : fd_(fd) {}
  int fd_;
};

}  // namespace ecat::pdi_spi
