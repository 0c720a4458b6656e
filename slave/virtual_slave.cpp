#include "slave/virtual_slave.hpp"

#include "slave/drive_application.hpp"
#include "slave/esc_setup.hpp"
#include "slave/firmware.hpp"

namespace ecat::slave {

Expected<std::unique_ptr<VirtualSlave>, std::string> VirtualSlave::create(od::DeviceDescription device,
                                                                         const Clock& clock,
                                                                         const SlaveOptions& options) {
  std::unique_ptr<VirtualSlave> s(new VirtualSlave());
  if (auto ok = check_drive(device); !ok) return fail(ok.error());
  s->device_ = std::make_unique<od::DeviceDescription>(std::move(device));
  auto config = esc_config_for(*s->device_);
  if (!config) return fail(config.error());
  s->esc_ = std::make_unique<esc::Esc>(std::move(*config), clock);
  s->esc_->dc().set_clock(options.clock_ppm, options.clock_start);
  s->firmware_ = std::make_unique<Firmware>(*s->esc_, *s->device_, options);
  return s;
}

VirtualSlave::~VirtualSlave() = default;

std::optional<Nanoseconds> VirtualSlave::poll(Nanoseconds now) noexcept {
  std::optional<Nanoseconds> next = esc_->poll(now);
  esc_next_ = next;
  esc_wake_ = next.value_or(Nanoseconds::max());
  // The firmware sleeps unless the ESC raised its IRQ or its deadline came.
  const std::optional<Nanoseconds> fw =
      firmware_->wants_poll(now) ? firmware_->poll(now) : firmware_->next_deadline();
  if (fw && (!next || *fw < *next)) next = fw;
  return next;
}

void VirtualSlave::after_frame(Nanoseconds now) noexcept {
  // SYNC pulses (and other ESC timers) due by now are raised before the
  // firmware looks: silicon raises them in time, the emulation on demand.
  if (esc_next_ && *esc_next_ <= now) {
    (void)poll(now);
  } else if (firmware_->wants_poll(now)) {
    (void)firmware_->poll(now);
  }
}

SlaveStatus VirtualSlave::status() const noexcept { return firmware_->status(); }

void VirtualSlave::shutdown() noexcept {}

}  // namespace ecat::slave
