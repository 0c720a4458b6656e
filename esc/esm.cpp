// EtherCAT state machine (ETG.1000.6 §6.4; shared/spec/esm-al-codes.md;
// behaviour where sources differ follows docs/esm.md).
#include "esc/esm.hpp"

#include "esc/esm_sm_check.hpp"
#include "esc/registers.hpp"

namespace ecat::esc {
namespace {

// Order of the states by the services they run; Bootstrap sits beside PreOp
// (both run a mailbox only).
int rank(AlState s) noexcept {
  switch (s) {
    case AlState::Init: return 0;
    case AlState::PreOp:
    case AlState::Bootstrap: return 1;
    case AlState::SafeOp: return 2;
    case AlState::Op: return 3;
  }
  return 0;
}

bool runs_mailbox(AlState s) noexcept { return s != AlState::Init; }
bool runs_process_data(AlState s) noexcept { return s == AlState::SafeOp || s == AlState::Op; }

}  // namespace

Esm::Esm(Pdi& pdi, const EsmConfig& config) noexcept : pdi_(pdi), config_(config) {}

bool Esm::add_hooks(EsmHooks& hooks) noexcept {
  if (hook_count_ == kMaxHooks) return false;
  hooks_[hook_count_++] = &hooks;
  return true;
}

bool Esm::remove_hooks(EsmHooks& hooks) noexcept {
  for (std::size_t i = 0; i < hook_count_; ++i) {
    if (hooks_[i] != &hooks) continue;
    for (std::size_t j = i + 1; j < hook_count_; ++j) hooks_[j - 1] = hooks_[j];
    hooks_[--hook_count_] = nullptr;
    return true;
  }
  return false;
}

bool Esm::add_deferral(EsmDeferral& deferral) noexcept {
  if (deferral_count_ == kMaxHooks) return false;
  deferrals_[deferral_count_++] = &deferral;
  return true;
}

bool Esm::deferrals_ready(AlState from, AlState to) noexcept {
  for (std::size_t i = 0; i < deferral_count_; ++i) {
    if (!deferrals_[i]->transition_ready(from, to)) return false;
  }
  return true;
}

void Esm::reset() noexcept {
  pending_.reset();
  state_ = AlState::Init;
  error_ = false;
  code_ = AlStatusCode::NoError;
  id_value_ = 0;
  apply_services(AlState::Init);
  write_status();
}

void Esm::poll() noexcept { handle_events(pdi_.read_u32(reg::kAlEventRequest), true); }

void Esm::poll(std::uint32_t events) noexcept { handle_events(events, false); }

void Esm::handle_events(std::uint32_t events, bool watchdog_polled) noexcept {
  const bool requested = (events & kAlEventAlControl) != 0;
  if (requested) handle_request(pdi_.read_u16(reg::kAlControl));  // the read clears the event
  if ((events & kAlEventSmActivation) != 0) handle_sm_change();
  handle_watchdog(events, watchdog_polled);
  if (!requested) retry_pending();
}

// A transition held by a deferral: the checks run again (a hook may give up
// with its code), then it completes once every deferral is ready.
void Esm::retry_pending() noexcept {
  if (!pending_) return;
  const AlState target = *pending_;
  const AlStatusCode code = check(lookup_transition(state_, target), state_, target);
  if (code != AlStatusCode::NoError) {
    pending_.reset();
    refuse(code);
    return;
  }
  if (!deferrals_ready(state_, target)) return;
  pending_.reset();
  carry_out(target, pending_control_);
}

// ETG.1000.6 §6.4.1.2 and SOES ESC_state: while ErrInd is set a request is
// ignored unless it carries the acknowledge bit or asks for Init.
void Esm::handle_request(std::uint16_t control) noexcept {
  pending_.reset();  // a new request replaces one still waiting
  const bool ack = (control & kAlErrorAck) != 0;
  const auto requested = static_cast<std::uint8_t>(control & kAlStateMask);
  if (error_ && !ack && requested != static_cast<std::uint8_t>(AlState::Init)) return;

  const std::optional<AlState> target = decode_al_state(requested);
  if (!target) {
    refuse(AlStatusCode::UnknownRequestedState);
    return;
  }
  const EsmTransition t = lookup_transition(state_, *target);
  if (t == EsmTransition::Refused) {
    refuse(AlStatusCode::InvalidRequestedStateChange);
    return;
  }
  if (t == EsmTransition::Stay) {
    // Acknowledge (or a repeated request): clears ErrInd and the code.
    if (error_) {
      error_ = false;
      code_ = AlStatusCode::NoError;
    }
  } else {
    const bool down = is_downward(t);
    const AlStatusCode code = down ? AlStatusCode::NoError : check(t, state_, *target);
    if (code != AlStatusCode::NoError) {
      refuse(code);
      return;
    }
    if (!down && !deferrals_ready(state_, *target)) {
      pending_ = *target;  // AL status stays as it is until ready
      pending_control_ = control;
      return;
    }
    carry_out(*target, control);
    return;
  }
  update_identification(control, *target);
  write_status();
}

void Esm::carry_out(AlState target, std::uint16_t control) noexcept {
  id_value_ = 0;
  enter(target, AlStatusCode::NoError, false);
  update_identification(control, target);
  write_status();
}

AlStatusCode Esm::check(EsmTransition t, AlState from, AlState to) noexcept {
  AlStatusCode code = AlStatusCode::NoError;
  switch (t) {
    case EsmTransition::IP:
      if (config_.has_mailbox) {
        code = check_mailbox(pdi_, config_.mailbox_out, config_.mailbox_in,
                             AlStatusCode::InvalidMailboxConfigurationPreOp);
      }
      break;
    case EsmTransition::IB:
      code = config_.bootstrap_supported
                 ? check_mailbox(pdi_, config_.boot_mailbox_out, config_.boot_mailbox_in,
                                 AlStatusCode::InvalidMailboxConfigurationBoot)
                 : AlStatusCode::BootstrapNotSupported;
      break;
    case EsmTransition::PS: code = check_process_sms(pdi_, config_); break;
    case EsmTransition::SO:
      if (config_.op_requires_outputs &&
          (pdi_.read_u16(reg::kWatchdogStatusProcessData) & kWatchdogProcessDataActive) == 0) {
        code = AlStatusCode::SyncManagerWatchdog;
      }
      break;
    default: break;
  }
  if (code != AlStatusCode::NoError) return code;
  code = ask_hooks(from, to);
  if (code == AlStatusCode::NoError && t == EsmTransition::PS) code = check_sm_overlap(pdi_);
  return code;
}

AlStatusCode Esm::ask_hooks(AlState from, AlState to) noexcept {
  for (std::size_t i = 0; i < hook_count_; ++i) {
    const AlStatusCode code = hooks_[i]->check_transition(from, to);
    if (code != AlStatusCode::NoError) return code;
  }
  return AlStatusCode::NoError;
}

// SOES ESC_sm_act_event: a master that touches the mailbox SMs in PreOp or
// above sends the slave to Init (0x0016); one that breaks SM2/SM3 in SafeOp
// or Op sends it to PreOp (0x001D/0x001E).
void Esm::handle_sm_change() noexcept {
  constexpr unsigned kSmsWatched = kMaxProcessSms;
  for (unsigned n = 0; n < kSmsWatched; ++n) (void)read_sm(pdi_, n);  // clears the event
  if (state_ == AlState::Bootstrap) {
    const AlStatusCode code = check_mailbox(pdi_, config_.boot_mailbox_out, config_.boot_mailbox_in,
                                            AlStatusCode::InvalidMailboxConfigurationBoot);
    if (code != AlStatusCode::NoError) raise_error(code, AlState::Init);
    return;
  }
  if (runs_mailbox(state_) && config_.has_mailbox) {
    const AlStatusCode code = check_mailbox(pdi_, config_.mailbox_out, config_.mailbox_in,
                                            AlStatusCode::InvalidMailboxConfigurationPreOp);
    if (code != AlStatusCode::NoError) {
      raise_error(code, AlState::Init);
      return;
    }
  }
  if (runs_process_data(state_)) {
    AlStatusCode code = check_process_sms(pdi_, config_);
    if (code == AlStatusCode::NoError) code = check_sm_overlap(pdi_);
    if (code != AlStatusCode::NoError) raise_error(code, AlState::PreOp);
  }
}

// ETG.1000.6 / SOES ecat_slv.c: process-data watchdog expiry in Op drops the
// slave to SafeOp with 0x001B; the ESC itself leaves the AL state alone.
// `polled`: in Op the status is read on every call, event or not (for a PDI
// whose watchdog event may be missed); otherwise only on AL event bit 6.
void Esm::handle_watchdog(std::uint32_t events, bool polled) noexcept {
  if ((events & kAlEventWatchdog) == 0 && !(polled && state_ == AlState::Op)) return;
  const std::uint16_t status = pdi_.read_u16(reg::kWatchdogStatusProcessData);
  if (state_ == AlState::Op && (status & kWatchdogProcessDataActive) == 0) {
    raise_error(AlStatusCode::SyncManagerWatchdog, AlState::SafeOp);
  }
}

void Esm::raise_error(AlStatusCode code, AlState target) noexcept {
  pending_.reset();
  if (rank(target) >= rank(state_)) target = state_;
  id_value_ = 0;
  enter(target, code, true);
}

void Esm::refuse(AlStatusCode code) noexcept {
  id_value_ = 0;
  code_ = code;
  error_ = true;
  write_status();
}

void Esm::enter(AlState to, AlStatusCode code, bool error) noexcept {
  const AlState from = state_;
  state_ = to;
  code_ = code;
  error_ = error;
  if (from != to) apply_services(to);
  write_status();
  if (from == to) return;
  for (std::size_t i = 0; i < hook_count_; ++i) hooks_[i]->on_state_changed(from, to, code);
}

// What each state runs (esm-al-codes.md §1): SM0/SM1 from PreOp (or Boot) on,
// SM2/SM3 in SafeOp and Op. Stopped services are PDI-deactivated (0x0807+8n
// bit 0, SOES ESC_SMdisable) so the master gets no working counter.
void Esm::apply_services(AlState s) noexcept {
  const bool mailbox = runs_mailbox(s);
  const bool process = runs_process_data(s);
  // Without a mailbox SM0/SM1 may carry process data (Beckhoff EK18xx).
  if (config_.has_mailbox) {
    set_sm_deactivated(pdi_, kSmMailboxOut, !mailbox);
    set_sm_deactivated(pdi_, kSmMailboxIn, !mailbox);
  }
  for (const ProcessSmConfig& p : config_.process()) set_sm_deactivated(pdi_, p.sm, !process);
}

// ESC datasheet Section II 0x0120 bit 5, SOES ESC_check_id_request: with no
// error pending and a request other than Bootstrap, load the identification
// value (application value or else the station alias) into 0x0134.
void Esm::update_identification(std::uint16_t control, AlState target) noexcept {
  id_value_ = 0;
  if ((control & kAlIdRequest) == 0 || error_ || target == AlState::Bootstrap) return;
  id_value_ = config_.device_id != 0 ? config_.device_id
                                     : pdi_.read_u16(reg::kConfiguredStationAlias);
}

// Code first, then status (SOES order; masters read 0x0134 after ErrInd).
void Esm::write_status() noexcept {
  const bool id_shown = id_value_ != 0;
  pdi_.write_u16(reg::kAlStatusCode, id_shown ? id_value_ : static_cast<std::uint16_t>(code_));
  auto status = static_cast<std::uint16_t>(state_);
  if (error_) status = static_cast<std::uint16_t>(status | kAlErrorIndication);
  if (id_shown) status = static_cast<std::uint16_t>(status | kAlIdLoaded);
  pdi_.write_u16(reg::kAlStatus, status);
}

}  // namespace ecat::esc
