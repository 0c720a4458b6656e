#include "pdi_spi/gpio_irq_line.hpp"

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <fmt/format.h>

namespace ecat::pdi_spi {

namespace {
constexpr char kConsumer[] = "ecat-slave";
constexpr int kNanosecondsPerMillisecond = 1'000'000;
}  // namespace

gpio_v2_line_request make_gpio_line_request(const GpioLineOptions& options) noexcept {
  gpio_v2_line_request r{};
  r.offsets[0] = options.offset;
  r.num_lines = 1;
  std::memcpy(r.consumer, kConsumer, sizeof kConsumer);
  r.config.flags = GPIO_V2_LINE_FLAG_INPUT | GPIO_V2_LINE_FLAG_EDGE_RISING;
  if (options.active_low) r.config.flags |= GPIO_V2_LINE_FLAG_ACTIVE_LOW;
  return r;
}

Expected<std::unique_ptr<GpioIrqLine>, std::string> GpioIrqLine::open(const GpioLineOptions& options) {
  const int chip = ::open(options.chip.c_str(), O_RDWR | O_CLOEXEC);
  if (chip < 0) return fail(fmt::format("{}: cannot open: {}", options.chip, std::strerror(errno)));
  gpio_v2_line_request r = make_gpio_line_request(options);
  const int rc = ::ioctl(chip, GPIO_V2_GET_LINE_IOCTL, &r);
  const int err = errno;
  ::close(chip);
  if (rc < 0) {
    return fail(fmt::format("{}: requesting line {}: {}", options.chip, options.offset, std::strerror(err)));
  }
  return std::unique_ptr<GpioIrqLine>(new GpioIrqLine(r.fd));
}

GpioIrqLine::~GpioIrqLine() { ::close(fd_); }

bool GpioIrqLine::asserted() noexcept {
  gpio_v2_line_values v{};
  v.mask = 1;
  if (::ioctl(fd_, GPIO_V2_LINE_GET_VALUES_IOCTL, &v) < 0) return false;
  return (v.bits & 1) != 0;
}

bool GpioIrqLine::wait(Nanoseconds timeout) noexcept {
  pollfd p{fd_, POLLIN, 0};
  const auto ms = static_cast<int>((timeout.count() + kNanosecondsPerMillisecond - 1) / kNanosecondsPerMillisecond);
  if (::poll(&p, 1, ms < 0 ? 0 : ms) <= 0) return false;
  gpio_v2_line_event events[16];
  (void)::read(fd_, events, sizeof events);  // drain; the level is what counts
  return true;
}

}  // namespace ecat::pdi_spi
