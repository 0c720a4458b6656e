#include "slave/virtual_slave.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "od/firmware.hpp"
#include "pdi_spi/emulated_et1100_spi.hpp"
#include "pdi_spi/emulated_lan9252.hpp"
#include "pdi_spi/et1100_spi_pdi.hpp"
#include "pdi_spi/lan9252_pdi.hpp"

#include "slave/drive_application.hpp"
#include "slave/esc_setup.hpp"
#include "slave/firmware.hpp"

namespace ecat::slave {

Expected<std::unique_ptr<VirtualSlave>, std::string> VirtualSlave::create(od::DeviceDescription device,
                                                                         const Clock& clock,
                                                                         const SlaveOptions& options) {
  return create(std::make_shared<const od::DeviceDescription>(std::move(device)), clock, options);
}

Expected<std::unique_ptr<VirtualSlave>, std::string> VirtualSlave::create(
    std::shared_ptr<const od::DeviceDescription> device, const Clock& clock, const SlaveOptions& options,
    std::uint8_t esc_memory_colour) {
  std::unique_ptr<VirtualSlave> s(new VirtualSlave());
  if (auto ok = check_drive(*device); !ok) return fail(ok.error());
  s->device_ = std::move(device);
  auto config = esc_config_for(*s->device_, options.delay_figures);
  if (!config) return fail(config.error());
  // Another process's firmware (SOES) meets silicon's SM event rule.
  if (options.external_firmware) config->sm_status_read_clears_event = false;
  config->memory_colour = esc_memory_colour;
  if (options.processing_delay) config->processing_delay = *options.processing_delay;
  if (options.forwarding_delay) {  // the slave's own figure, every port alike
    config->forwarding_delay = *options.forwarding_delay;
    config->port_forwarding_delay.fill(std::nullopt);
  }
  s->esc_ = std::make_unique<esc::Esc>(std::move(*config), clock);
  s->esc_->dc().set_clock(options.clock_ppm, options.clock_start);
  s->has_firmware_ = od::runs_firmware(*s->device_);
  if (!s->has_firmware_ && options.pdi != PdiKind::Direct) {
    return fail(std::string("the device has no PDI (0x0140 PDI type 0, an ESC that only forwards): "
                            "there is no firmware to run over SPI"));
  }
  esc::Pdi* pdi = s->esc_.get();
  if (options.external_firmware) {
    if (options.pdi != PdiKind::Direct) return fail(std::string("an external firmware brings its own PDI"));
    s->has_firmware_ = false;
    s->detached_ = std::make_unique<DetachedPdi>();
    pdi = s->detached_.get();
  }
  s->options_ = options;
  if (options.pdi != PdiKind::Direct && !options.external_firmware) {
    if (auto ok = s->make_spi_pdi(); !ok) return fail(ok.error());
    pdi = s->spi_pdi_.get();
  }
  s->firmware_ = std::make_unique<Firmware>(*pdi, *s->device_, options);
  s->firmware_->keep_due_in(&s->fw_due_);
  return s;
}

Expected<void, std::string> VirtualSlave::make_spi_pdi() {
  if (options_.pdi == PdiKind::Lan9252) {
    chip_ = std::make_unique<pdi_spi::EmulatedLan9252>(*esc_);
    auto backend = std::make_unique<pdi_spi::Lan9252Pdi>(*chip_, options_.lan9252);
    if (!backend->init()) return fail(fmt::format("LAN9252 bring-up: {}", backend->error()));
    spi_pdi_ = std::move(backend);
  } else {
    chip_ = std::make_unique<pdi_spi::EmulatedEt1100Spi>(*esc_);
    spi_pdi_ = std::make_unique<pdi_spi::Et1100SpiPdi>(*chip_);
  }
  return {};
}

Expected<void, std::string> VirtualSlave::power_on() {
  esc_->reset();  // power-up register values, EEPROM loaded (Section II 0x0000-0x0F00 reset values)
  firmware_.reset();  // the µC starts from scratch: its parameter store is opened again
  esc::Pdi* pdi = detached_ ? static_cast<esc::Pdi*>(detached_.get()) : esc_.get();
  if (spi_pdi_) {
    // The SPI chip loses power too: a new one, and the firmware's bring-up
    // over SPI (LAN9252: byte test, ready bit) as at start-up.
    spi_pdi_.reset();
    chip_.reset();
    if (auto ok = make_spi_pdi(); !ok) return fail(ok.error());
    pdi = spi_pdi_.get();
  }
  firmware_ = std::make_unique<Firmware>(*pdi, *device_, options_);
  firmware_->keep_due_in(&fw_due_);
  if (probe_) firmware_->attach_trace(*probe_);
  esc_wake_ = Nanoseconds::max();
  return {};
}

VirtualSlave::~VirtualSlave() {
  // The order the members had before the hot ones moved first: whatever
  // sits on a PDI goes before the PDI, the PDIs before the ESC.
  detached_.reset();
  firmware_.reset();
  spi_pdi_.reset();
  chip_.reset();
  esc_.reset();
}

Nanoseconds VirtualSlave::advance(Nanoseconds now) noexcept {
  esc_wake_ = esc_->advance(now);
  // The firmware sleeps unless the ESC raised its IRQ or its deadline came.
  if (!has_firmware_) return esc_wake_;
  const Nanoseconds fw =
      firmware_->wants_poll(now, lines()) ? run_firmware(now) : firmware_->wake_time();
  return std::min(esc_wake_, fw);
}

Nanoseconds VirtualSlave::run_firmware(Nanoseconds now) noexcept {
  esc_->pin_pdi_time();
  const Nanoseconds wake = firmware_->advance(now, lines());
  esc_->unpin_pdi_time();
  return wake;
}

void VirtualSlave::after_frame(Nanoseconds now) noexcept {
  // SYNC pulses (and other ESC timers) due by now are raised before the
  // firmware looks: silicon raises them in time, the emulation on demand.
  if (esc_wake_ <= now) {  // max when the ESC has nothing armed
    (void)advance(now);
  } else if (has_firmware_ && firmware_->wants_poll(now, lines())) {
    (void)run_firmware(now);
  }
}

void VirtualSlave::attach_trace(esc::VcdProbe& probe) noexcept {
  probe_ = &probe;
  firmware_->attach_trace(probe);
  esc_->dc().set_observer(&probe);
}

SlaveStatus VirtualSlave::status() const noexcept {
  SlaveStatus s = firmware_->status();
  if (!has_firmware_) {
    // No µC: the state is what the ESC shows (device emulation).
    s.state = static_cast<esc::AlState>(esc_->memory()[esc::reg::kAlStatus] & esc::bits::kAlStateMask);
  }
  if (detached_) {
    // A firmware in another process: what it left in AL status and code.
    s.error = (esc_->memory()[esc::reg::kAlStatus] & esc::bits::kAlErrorInd) != 0;
    s.code = static_cast<esc::AlStatusCode>(load_le<std::uint16_t>(esc_->memory() + esc::reg::kAlStatusCode));
  }
  // The ESC counts process-data watchdog expiries itself (0x0442, saturating).
  s.watchdog_expiries = esc_->memory()[esc::reg::kWatchdogCounterProcessData];
  return s;
}

void VirtualSlave::shutdown() noexcept {}

}  // namespace ecat::slave
