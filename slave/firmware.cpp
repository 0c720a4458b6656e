#include "slave/firmware.hpp"

#include "esc/registers.hpp"
#include "slave/drive_application.hpp"
#include "slave/esc_setup.hpp"

namespace ecat::slave {
namespace {

bool has_type(const od::DeviceDescription& device, od::SmType type) {
  for (const auto& sm : device.sync_managers) {
    if (sm.type == type) return true;
  }
  return false;
}

coe::CoeOptions coe_options(const SlaveOptions& o) {
  coe::CoeOptions c;
  if (!o.state_dir.empty()) {
    c.parameter_file = (o.state_dir / (o.name + ".par")).string();
    c.foe_dir = (o.state_dir / (o.name + "-foe")).string();
  }
  return c;
}

// Time step of an application cycle that has no previous cycle to measure from.
constexpr Nanoseconds kNominalCycle = std::chrono::milliseconds(1);

bool is_operational(esc::AlState s) { return s == esc::AlState::SafeOp || s == esc::AlState::Op; }

}  // namespace

Firmware::Firmware(esc::Esc& esc, const od::DeviceDescription& device, const SlaveOptions& options)
    : esc_(esc),
      esm_(esc, esm_config_for(device)),
      coe_(esc, device, coe_options(options)),
      sync_(esc, coe_.objects(), device.sync, has_type(device, od::SmType::Outputs),
            has_type(device, od::SmType::Inputs)) {
  esm_.add_hooks(coe_.esm_hooks());
  sync_.install();
  sync_.attach(esm_);
  app_ = make_drive_application(device, coe_, options.motion_trace);
  esm_.reset();
}

void Firmware::attach_trace(esc::VcdProbe& probe) noexcept {
  trace_ = &probe;
  esm_.add_hooks(probe);
  esc_.dc().set_observer(&probe);
  sync_.set_trace(&probe);
}

std::optional<Nanoseconds> Firmware::poll(Nanoseconds now) noexcept {
  const esc::AlState before = esm_.state();
  esm_.poll();
  const esc::AlState after = esm_.state();
  if (after != before) {
    if (app_) app_->on_state(after);
    if (!is_operational(after)) last_cycle_.reset();
  }
  coe_.poll(now);
  const coe::SyncPoll sp = sync_.poll(now);
  if (sp.run && is_operational(esm_.state())) application_cycle(now);
  return sp.next;
}

void Firmware::application_cycle(Nanoseconds now) noexcept {
  const bool op = esm_.state() == esc::AlState::Op;
  if (op) coe_.process_data().read_outputs(esc_);
  // The first cycle after entering SafeOp has no predecessor: it counts as
  // one nominal cycle, so the application never sees a zero time step.
  const Nanoseconds dt = last_cycle_ && now > *last_cycle_ ? now - *last_cycle_ : kNominalCycle;
  last_cycle_ = now;
  if (app_) app_->cycle(dt, op);
  coe_.process_data().write_inputs(esc_);
  sync_.cycle_done(now);
  ++cycles_;
}

SlaveStatus Firmware::status() const noexcept {
  SlaveStatus s;
  s.state = esm_.state();
  s.error = esm_.error_indicated();
  s.code = esm_.status_code();
  s.application_cycles = cycles_;
  // The ESC counts process-data watchdog expiries itself (0x0442, saturating).
  s.watchdog_expiries = esc_.memory()[esc::reg::kWatchdogCounterProcessData];
  s.sync_errors = sync_.sm_events_missed();
  return s;
}

}  // namespace ecat::slave
