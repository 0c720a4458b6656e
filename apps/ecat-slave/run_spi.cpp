// ecat-slave --pdi: the firmware of one device (ESM, mailbox, CoE, the
// CiA402 drive) on a real EtherCAT slave controller behind Linux spidev -
// a LAN9252 or an ET1100/ET1200 SPI PDI. The ESC's EEPROM must hold the
// SII image `ecat-esigen --sii` wrote for the same device file, so the
// master sees the identity and SM layout this firmware checks against.
// Written against the data sheets and tested over the emulated chips
// (pdi_spi/emulated_*); not yet run on hardware (docs/real-esc.md).
#include <csignal>
#include <cstdio>
#include <memory>
#include <optional>
#include <thread>

#include <fmt/format.h>

#include "apps/ecat-slave/runners.hpp"
#include "common/clock.hpp"
#include "pdi_spi/et1100_spi_pdi.hpp"
#include "pdi_spi/gpio_irq_line.hpp"
#include "pdi_spi/lan9252_pdi.hpp"
#include "pdi_spi/pdi_spec.hpp"
#include "pdi_spi/spidev_bus.hpp"
#include "slave/drive_application.hpp"
#include "slave/firmware.hpp"

namespace ecat::app {
namespace {

volatile std::sig_atomic_t g_stop = 0;
void on_stop(int) { g_stop = 1; }

// Without an IRQ line the firmware looks at the ESC this often.
constexpr Nanoseconds kPollPeriod = std::chrono::microseconds(250);
// Longest sleep with an IRQ line, so signals are seen promptly.
constexpr Nanoseconds kMaxWait = std::chrono::milliseconds(50);

Expected<pdi_spi::GpioLineOptions, std::string> parse_gpio(const std::string& text) {
  const std::size_t colon = text.rfind(':');
  if (colon == std::string::npos) return fail(fmt::format("--irq-gpio {}: expected CHIP:LINE", text));
  pdi_spi::GpioLineOptions g;
  g.chip = text.substr(0, colon);
  try {
    g.offset = static_cast<std::uint32_t>(std::stoul(text.substr(colon + 1)));
  } catch (const std::exception&) {
    return fail(fmt::format("--irq-gpio {}: line is not a number", text));
  }
  return g;
}

}  // namespace

int run_spi(const SlaveProgramOptions& o, std::vector<od::DeviceDescription> devices) {
  auto fail_with = [](const std::string& what) {
    std::fprintf(stderr, "ecat-slave: %s\n", what.c_str());
    return 1;
  };
  if (devices.size() != 1) return fail_with("--pdi runs the firmware of exactly one device");
  auto spec = pdi_spi::parse_pdi_spec(o.pdi);
  if (!spec) return fail_with(fmt::format("--pdi {}", spec.error()));
  if (auto ok = slave::check_drive(devices[0]); !ok) return fail_with(ok.error());
  std::optional<pdi_spi::GpioLineOptions> gpio;
  if (!o.irq_gpio.empty()) {
    auto g = parse_gpio(o.irq_gpio);
    if (!g) return fail_with(g.error());
    gpio = *g;
  }

  pdi_spi::SpidevOptions so;
  so.device = spec->device;
  so.speed_hz = o.spi_hz;
  so.mode = static_cast<std::uint8_t>(o.spi_mode);
  auto bus = pdi_spi::SpidevBus::open(so);
  if (!bus) return fail_with(bus.error());
  std::unique_ptr<pdi_spi::GpioIrqLine> irq;
  if (gpio) {
    auto line = pdi_spi::GpioIrqLine::open(*gpio);
    if (!line) return fail_with(line.error());
    irq = std::move(*line);
  }

  std::unique_ptr<pdi_spi::SpiPdi> pdi;
  if (spec->chip == pdi_spi::SpiChip::Lan9252) {
    pdi_spi::Lan9252Options lo;
    if (o.lan9252_lean) lo = {.fast_read = true, .burst_setup = true, .skip_csr_poll = true};
    auto lan = std::make_unique<pdi_spi::Lan9252Pdi>(**bus, lo);
    if (!lan->init()) return fail_with(fmt::format("{}: LAN9252 bring-up: {}", spec->device, lan->error()));
    pdi = std::move(lan);
  } else {
    pdi = std::make_unique<pdi_spi::Et1100SpiPdi>(**bus);
  }

  slave::SlaveOptions options;
  options.state_dir = o.state_dir;
  options.name = "slave-1";
  slave::Firmware firmware(*pdi, devices[0], options);
  if (pdi->failed()) return fail_with(fmt::format("{}: {}", spec->device, pdi->error()));

  struct sigaction sa {};
  sa.sa_handler = on_stop;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  if (!o.quiet) {
    fmt::print("ecat-slave: {} firmware on {} ({} Hz, mode {}), {}\n", devices[0].identity.name, o.pdi, o.spi_hz, o.spi_mode,
               irq ? "IRQ on " + o.irq_gpio : "polling every 250 us");
  }

  SteadyClock clock;
  while (g_stop == 0) {
    const Nanoseconds now = clock.now();
    // A real chip keeps the mask it was given (an ESC reset there resets
    // the µC as well), so the mask the firmware programmed is the one held.
    const slave::EscLines lines{irq ? irq->asserted() : true, firmware.event_mask()};
    std::optional<Nanoseconds> next = firmware.next_deadline();
    if (firmware.wants_poll(now, lines)) next = firmware.poll(now, lines);
    if (pdi->failed()) return fail_with(fmt::format("{}: {}", spec->device, pdi->error()));
    const Nanoseconds until = next ? std::max(Nanoseconds{0}, *next - clock.now()) : kMaxWait;
    if (irq) {
      (void)irq->wait(std::min(until, kMaxWait));
    } else {
      std::this_thread::sleep_for(std::min(until, kPollPeriod));
    }
  }
  const auto& c = pdi->counters();
  const auto st = firmware.status();
  if (!o.quiet) {
    fmt::print("ecat-slave: {} firmware passes, {} application cycles, {} SPI transactions, {} bytes\n",
               st.firmware_polls, st.application_cycles, c.transactions, c.bytes);
  }
  return 0;
}

}  // namespace ecat::app
