#include "slave/firmware.hpp"

#include "coe/sm_bits.hpp"
#include "common/le.hpp"
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

coe::CoeOptions coe_options(const SlaveOptions& o, coe::StorageQuota* quota) {
  coe::CoeOptions c;
  c.eoe_defaults = o.eoe;
  c.foe_password = o.foe_password;
  c.foe_busy = o.foe_busy;
  if (!o.state_dir.empty()) {
    c.parameter_file = (o.state_dir / (o.name + ".par")).string();
    c.foe_dir = (o.state_dir / (o.name + "-foe")).string();
    c.state_quota = quota;
  }
  return c;
}

// The quota over the state directory: the one given, or one of this slave's
// own with the default limits over what the directory already holds.
std::shared_ptr<coe::StorageQuota> quota_for(const SlaveOptions& o) {
  if (o.state_dir.empty() || o.state_quota) return o.state_quota;
  auto q = std::make_shared<coe::StorageQuota>(coe::StorageQuota::Limits{});
  (void)q->count_existing(o.state_dir);
  return q;
}

// Time step of an application cycle that has no previous cycle to measure from.
constexpr Nanoseconds kNominalCycle = std::chrono::milliseconds(1);

bool is_operational(esc::AlState s) { return s == esc::AlState::SafeOp || s == esc::AlState::Op; }

// SyncManager control 0x0804+8n bit 5: the SM raises its AL event (Section II).
constexpr std::uint8_t kSmControlAlEvent = 0x20;
constexpr std::uint32_t kAlEventSmShift = 8;  // 0x0220 bit 8+n: SM n
constexpr unsigned kSmsWithEvents = 4;        // mailbox and process-data SMs
// Events every state handles: AL control, SM activation, watchdog, mailbox.
constexpr std::uint32_t kBaseEvents = esc::Esm::kEventsHandled | coe::MailboxServer::kEventsHandled;
// Events the mailbox reacts to, SM activation included (repeat request).
constexpr std::uint32_t kMailboxEvents = coe::MailboxServer::kEventsHandled | esc::kAlEventSmActivation;

}  // namespace

Firmware::Firmware(esc::Pdi& pdi, const od::DeviceDescription& device, const SlaveOptions& options)
    : pdi_(pdi),
      esm_(pdi, esm_config_for(device)),
      state_quota_(quota_for(options)),
      coe_(pdi, device, coe_options(options, state_quota_.get())),
      sync_(pdi, coe_.objects(), device.sync, has_type(device, od::SmType::Outputs),
            has_type(device, od::SmType::Inputs)),
      eoe_init_(options.eoe_init),
      report_(options.report) {
  coe_.mailbox().keep_idle_flag(&mailbox_idle_);
  esm_.add_hooks(coe_.esm_hooks());
  sync_.install();
  sync_.attach(esm_);
  app_ = make_drive_application(device, coe_, options.motion_trace);
  esm_.reset();
  // At power-on the ESC's mask is 0 (Section II 0x0204): program it.
  program_event_mask(true, EscLines{});
  // What poll() would leave: without it a slave nobody talks to (Init, no
  // IRQ) stayed pending() until its first poll, which wants_poll() never
  // asked for - and a chain visited it at every frame and every poll.
  due_->pass_work = poll_each_frame_ || esm_.pending() || coe_.mailbox().has_output();
}

void Firmware::attach_trace(esc::VcdProbe& probe) noexcept {
  trace_ = &probe;
  esm_.add_hooks(probe);
  sync_.set_trace(&probe);
}

Nanoseconds Firmware::advance(Nanoseconds now, EscLines lines) noexcept {
  ++polls_;
  // One read of 0x0220 for the pass, in every mode, as SSC's and SOES's
  // interrupt handlers do. DC mode read it again in the ESM and the
  // synchronisation until session 31: the e2e DC run over veth had lost SYNC
  // events with the one read (0x0034/0x001A), a cause found since - a SYNC
  // pulse latched before PreOp->SafeOp taken as live (SyncController,
  // discard_sync_events_); docs/performance-log.md "Session 31".
  const std::uint32_t events = pdi_.read_u32(esc::reg::kAlEventRequest);
  if ((events & esc::Esm::kEventsHandled) != 0 || esm_.pending()) esm_.poll(events);
  if (esm_.status_code() != code_seen_) note_al_status_code(now);
  const esc::AlState state = esm_.state();
  const bool changed = state != state_seen_;
  if (changed) {
    state_seen_ = state;
    if (app_) app_->on_state(state);
    if (!is_operational(state)) last_cycle_.reset();
    if (!eoe_init_.empty()) check_eoe_init(state);
  }
  const bool sms_changed = changed || (events & esc::kAlEventSmActivation) != 0;
  if (sms_changed) coe_.process_data().load_layout(pdi_);
  if (changed || (events & kMailboxEvents) != 0 || mailbox_output()) coe_.poll(now);
  const coe::SyncPoll sp = sync_.poll(now, events);
  if (sp.run && is_operational(esm_.state())) application_cycle(now);
  program_event_mask(sms_changed, lines);
  Due& due = *due_;
  due.wake = sp.next.value_or(kNoDeadline);
  due.pass_work = poll_each_frame_ || esm_.pending() || mailbox_output();
  return due.wake;
}

// A new AL status code (an error the ESM raised or a refused transition)
// goes into the diagnosis history 10F3h when the device has one (ETG.1020
// §13; Diag Code E001h with the code, docs/coe.md "Diagnosis history").
void Firmware::note_al_status_code(Nanoseconds now) noexcept {
  code_seen_ = esm_.status_code();
  if (code_seen_ == esc::AlStatusCode::NoError) return;
  (void)coe_.diagnosis().add(coe::DiagnosisHistory::from_al_status(static_cast<std::uint16_t>(code_seen_)), now);
}

// The ENI's EoE InitCmds due by the state just entered (SafeOp: those of
// IP and PS; Op: SO) against what the master set (docs/eoe.md "ENI EoE
// InitCmds"). Runs on state changes only, never per frame.
void Firmware::check_eoe_init(esc::AlState entered) noexcept {
  for (const auto& x : eoe_init_) {
    if (x.due != entered) continue;
    eoe_init_results_.push_back(slave::check_eoe_init(x, coe_.eoe().ip_parameters()));
    if (report_) report_(eoe_init_results_.back().text);
  }
}

// ETG.1000.4 §6.2 / ESC datasheet Section II 0x0204: the IRQ to the µC is
// AL event request & mask. Rewritten only when the set changes (state or
// synchronisation mode).
void Firmware::program_event_mask(bool sms_changed, EscLines lines) noexcept {
  const std::uint32_t mask = kBaseEvents | sync_.al_event_mask();
  if (mask != due_->event_mask || mask_lost(lines)) {
    pdi_.write_u32(esc::reg::kAlEventMask, mask);
    due_->event_mask = mask;
    sms_changed = true;
  }
  if (sms_changed) poll_each_frame_ = !sm_events_enabled(mask);
}

// An enabled SM the firmware waits on whose control byte does not raise the
// AL event (a master may configure it so): the firmware then looks after
// every frame, as polled firmware does.
bool Firmware::sm_events_enabled(std::uint32_t mask) noexcept {
  for (unsigned n = 0; n < kSmsWithEvents; ++n) {
    if ((mask & (1u << (kAlEventSmShift + n))) == 0) continue;
    const auto base = esc::reg::sync_manager(n);
    const std::uint8_t control = pdi_.read_u8(static_cast<std::uint16_t>(base + esc::reg::sm::kControl));
    const std::uint8_t activate = pdi_.read_u8(static_cast<std::uint16_t>(base + esc::reg::sm::kActivate));
    if ((activate & coe::bits::kSmActivateEnable) != 0 && (control & kSmControlAlEvent) == 0) return false;
  }
  return true;
}

void Firmware::application_cycle(Nanoseconds now) noexcept {
  const bool op = esm_.state() == esc::AlState::Op;
  if (op) coe_.process_data().read_outputs(pdi_);
  // The first cycle after entering SafeOp has no predecessor: it counts as
  // one nominal cycle, so the application never sees a zero time step.
  const Nanoseconds dt = last_cycle_ && now > *last_cycle_ ? now - *last_cycle_ : kNominalCycle;
  last_cycle_ = now;
  if (app_) app_->cycle(dt, op);
  coe_.process_data().write_inputs(pdi_);
  sync_.cycle_done(now);
  ++cycles_;
}

SlaveStatus Firmware::status() const noexcept {
  SlaveStatus s;
  s.state = esm_.state();
  s.error = esm_.error_indicated();
  s.code = esm_.status_code();
  s.application_cycles = cycles_;
  s.firmware_polls = polls_;
  s.sync_errors = sync_.sm_events_missed();
  return s;
}

}  // namespace ecat::slave
