// Synchronisation modes at run time; behaviour in sync_controller.hpp,
// choices in docs/dc.md.
#include "coe/sync_controller.hpp"

#include <algorithm>

#include "esc/dc/dc_registers.hpp"
#include "coe/sm_bits.hpp"
#include "esc/registers.hpp"

namespace ecat::coe {
namespace {

using esc::AlState;
using esc::AlStatusCode;

constexpr unsigned kOutputsSm = 2;
constexpr std::uint32_t kAlEventSm3 = 1u << (8 + 3);  // AL event 0x0220 bit 8+n
constexpr std::uint8_t kSmStatusBufferMask = 0x30;    // SM status bits 5:4
constexpr unsigned kSmStatusBufferShift = 4;
constexpr std::uint8_t kNoBufferWritten = 3;
constexpr std::uint8_t kSmControlModeMask = 0x03;
constexpr std::uint16_t dc_register(std::uint16_t offset) { return static_cast<std::uint16_t>(esc::reg::kDcBase + offset); }

bool at_least_safeop(AlState s) noexcept { return s == AlState::SafeOp || s == AlState::Op; }

}  // namespace

SyncController::SyncController(esc::Pdi& pdi, ObjectStore& store, const od::SyncLimits& limits, bool has_outputs,
                               bool has_inputs) noexcept
    : limits_(limits), has_outputs_(has_outputs), pdi_(pdi), store_(store), has_inputs_(has_inputs) {}

void SyncController::install() noexcept {
  std::uint16_t supported = 0;
  if (limits_.free_run) supported |= kSupportsFreeRun;
  if (limits_.sm_synchronous) supported |= kSupportsSmSynchronous;
  if (limits_.dc_sync0 || limits_.dc_sync1) supported |= kSupportsDc;
  if (limits_.dc_sync1) supported |= kSupportsSync1Shift;
  for (const std::uint16_t index : {kSmOutputParameter, kSmInputParameter}) {
    store_.set_hooks(index, this);
    if (store_.get<std::uint16_t>(index, syncsub::kSyncModesSupported) == 0) {
      (void)store_.set(index, syncsub::kSyncModesSupported, supported);
    }
    const auto given_min = store_.get<std::uint32_t>(index, syncsub::kMinimumCycleTime);
    if (given_min == 0) {
      (void)store_.set(index, syncsub::kMinimumCycleTime, limits_.min_cycle_time_ns);
    } else if (index == kSmOutputParameter && given_min > limits_.min_cycle_time_ns) {
      // The dictionary's own minimum (a vendor ESI's 1C32h:05 DefaultData)
      // is what a master reads: the PreOp->SafeOp check holds to it too
      // (0x0036 below it), so the slave does not accept what it says it cannot.
      limits_.min_cycle_time_ns = given_min;
    }
  }
  load_modes();
  cycle_slot_ = store_.slot(kSmOutputParameter, syncsub::kCycleTime);
  cycle_bytes_ = plain_unsigned(cycle_slot_, sizeof(std::uint32_t));
  error_limit_bytes_ =
      plain_unsigned(store_.slot(kErrorSettings, kErrorSettingsSyncErrorLimit), sizeof(std::uint16_t));
  calc_copy_bytes_ = plain_unsigned(store_.slot(kSmOutputParameter, syncsub::kCalcAndCopyTime), sizeof(std::uint32_t));
}

// An unsigned integer of `bytes` bytes as the dictionaries define 1C32h:02,
// 1C32h:06 and 10F1h:02: its value bytes are the value, read in place each
// cycle (issue 8); null for anything else (read through the store).
const std::uint8_t* SyncController::plain_unsigned(const ObjectStore::Slot* s, std::uint32_t bytes) noexcept {
  return s != nullptr && s->capacity == bytes && store_.length(*s) == bytes && !od::is_signed(s->entry->type)
             ? store_.value(*s).data()
             : nullptr;
}

void SyncController::load_modes() noexcept {
  mode_[0] = static_cast<SyncMode>(store_.get<std::uint16_t>(kSmOutputParameter, syncsub::kSyncMode));
  mode_[1] = static_cast<SyncMode>(store_.get<std::uint16_t>(kSmInputParameter, syncsub::kSyncMode));
}

bool SyncController::attach(esc::Esm& esm) noexcept {
  esm_ = &esm;
  return esm.add_hooks(*this) && esm.add_deferral(*this);
}

Expected<void, SdoAbort> SyncController::on_write(ObjectStore& store, const WriteRequest& request) noexcept {
  (void)store;
  const auto value = static_cast<std::uint16_t>(load_bits(request.data, 16, false));
  if (request.subindex == syncsub::kSyncMode &&
      !is_defined_sync_mode(value, request.index == kSmInputParameter)) {
    return fail(SdoAbort::ValueRange);
  }
  if (request.subindex == syncsub::kGetCycleTime && value > kGetCycleTimeReset) return fail(SdoAbort::ValueRange);
  return {};
}

void SyncController::after_write(ObjectStore& store, std::uint16_t index, std::uint8_t subindex) noexcept {
  const std::size_t i = index == kSmOutputParameter ? 0 : 1;
  if (subindex == syncsub::kSyncMode) {
    mode_written_[i] = true;
    mode_[i] = static_cast<SyncMode>(store.get<std::uint16_t>(index, subindex));
  } else if (subindex == syncsub::kGetCycleTime && store.get<std::uint16_t>(index, subindex) == kGetCycleTimeReset) {
    reset_counters();
    (void)store.set(index, subindex, std::uint16_t{0});
  }
}

SyncSettings SyncController::settings() noexcept {
  SyncSettings s;
  s.has_outputs = has_outputs_;
  s.has_inputs = has_inputs_;
  s.dc_activation = pdi_.read_u8(dc_register(esc::dcreg::kActivation));
  s.sync0_cycle = pdi_.read_u32(dc_register(esc::dcreg::kSync0CycleTime));
  s.sync1_cycle = pdi_.read_u32(dc_register(esc::dcreg::kSync1CycleTime));
  const std::uint8_t control =
      pdi_.read_u8(static_cast<std::uint16_t>(esc::reg::sync_manager(kOutputsSm) + esc::reg::sm::kControl));
  s.outputs_three_buffer = (control & kSmControlModeMask) == 0;
  // A cycle time the master cannot write (read-only 1C32h:02, as some drives
  // list it) reflects the SYNC0 cycle the master programmed (ETG.1020 SM
  // synchronisation: "cycle time of SYNC0" in DC mode) instead of being
  // compared with it.
  const auto* cycle_slot = store_.slot(kSmOutputParameter, syncsub::kCycleTime);
  if (cycle_slot != nullptr && !cycle_slot->entry->access.writable() && s.sync0_cycle != 0) {
    (void)store_.set(kSmOutputParameter, syncsub::kCycleTime, s.sync0_cycle);
  }
  s.cycle_time = store_.get<std::uint32_t>(kSmOutputParameter, syncsub::kCycleTime);
  mode_[0] = derive_sync_mode(mode_written_[0], mode_[0], s.dc_activation, limits_, SyncMode::SmSynchronous);
  if (!mode_written_[1] && mode_written_[0] && has_outputs_) {
    // Only 1C32h:01 written: the inputs follow the outputs (ETG.1020).
    mode_[1] = mode_[0] == SyncMode::SmSynchronous ? SyncMode::SmSynchronousSm2 : mode_[0];
  } else {
    mode_[1] = derive_sync_mode(mode_written_[1], mode_[1], s.dc_activation, limits_,
                                has_outputs_ ? SyncMode::SmSynchronousSm2 : SyncMode::SmSynchronous);
  }
  (void)store_.set(kSmOutputParameter, syncsub::kSyncMode, static_cast<std::uint16_t>(mode_[0]));
  (void)store_.set(kSmInputParameter, syncsub::kSyncMode, static_cast<std::uint16_t>(mode_[1]));
  s.output_mode = mode_[0];
  s.input_mode = mode_[1];
  return s;
}

SyncMode SyncController::trigger_mode() const noexcept { return has_outputs_ ? mode_[0] : mode_[1]; }

AlStatusCode SyncController::check_transition(AlState from, AlState to) noexcept {
  if (from == AlState::PreOp && to == AlState::SafeOp) {
    const SyncSettings s = settings();
    const AlStatusCode code = check_sync_for_safeop(s, limits_);
    if (code == AlStatusCode::NoError) sync0_cycle_ = s.sync0_cycle;
    return code;
  }
  if (from == AlState::SafeOp && to == AlState::Op && is_dc(trigger_mode()) &&
      syncs_in_safeop_ < kSyncPulsesBeforeOp) {
    if (!op_wait_start_) op_wait_start_ = last_now_;
    if (last_now_ - *op_wait_start_ >= kSyncWaitTimeout) {
      op_wait_start_.reset();
      return AlStatusCode::NoSyncError;  // never synchronised (0x002D)
    }
  }
  return AlStatusCode::NoError;
}

bool SyncController::transition_ready(AlState from, AlState to) noexcept {
  if (from != AlState::SafeOp || to != AlState::Op || !is_dc(trigger_mode())) return true;
  return syncs_in_safeop_ >= kSyncPulsesBeforeOp;
}

void SyncController::on_state_changed(AlState from, AlState to, AlStatusCode code) noexcept {
  (void)code;
  state_ = to;
  op_wait_start_.reset();
  if (from == AlState::PreOp && to == AlState::SafeOp) {
    reset_counters();
    syncs_in_safeop_ = 0;
    last_sync_.reset();
    timeout_reported_ = false;
    // A SYNC0/SYNC1 pulse latched before (0x098E/0x098F and the AL event bit
    // stay set until the PDI reads the status, ESC Section II 0x098E; the
    // firmware does not look in Init/PreOp) is from an earlier run of the
    // SYNC unit (a master that left the unit running from Op to Init), not
    // of the one just programmed: taken as a live pulse it starts the SYNC
    // timeout long before the new start time and drops the slave with
    // 0x0034. The firmware clears it as it starts the cycle, including from
    // the AL event snapshot of the poll that made this transition.
    (void)pdi_.read_u8(dc_register(esc::dcreg::kSync0Status));
    (void)pdi_.read_u8(dc_register(esc::dcreg::kSync1Status));
    discard_sync_events_ = true;  // and in the snapshot the current poll already took
  }
  if (to == AlState::Op) {
    error_counter_ = 0;
    outputs_since_sync_ = true;  // the master sent outputs before asking for Op
  }
  if (!at_least_safeop(to)) sm2_buffer_.reset();
}

SyncPoll SyncController::poll(Nanoseconds now) noexcept { return poll(now, pdi_.read_u32(esc::reg::kAlEventRequest)); }

std::uint32_t SyncController::al_event_mask() const noexcept {
  if (!at_least_safeop(state_)) return 0;
  const std::uint32_t process = has_outputs_ ? bits::al_event_sm(kOutputsSm) : kAlEventSm3;
  switch (trigger_mode()) {
    case SyncMode::FreeRun: return 0;
    case SyncMode::SmSynchronous:
    case SyncMode::SmSynchronousSm2: return process;
    // New outputs are noted as they come (shift time check); the cycle runs on SYNC.
    case SyncMode::DcSync0: return esc::dcreg::kAlEventSync0 | (has_outputs_ ? process : 0);
    case SyncMode::DcSync1: return esc::dcreg::kAlEventSync1 | (has_outputs_ ? process : 0);
  }
  return 0;
}

SyncPoll SyncController::poll(Nanoseconds now, std::uint32_t al_events) noexcept {
  events_ = al_events;
  if (discard_sync_events_) {
    // The snapshot may predate the acknowledge at PreOp->SafeOp: its SYNC
    // bits are taken from the register as it is now.
    constexpr std::uint32_t kSyncEvents = esc::dcreg::kAlEventSync0 | esc::dcreg::kAlEventSync1;
    events_ = (events_ & ~kSyncEvents) | (pdi_.read_u32(esc::reg::kAlEventRequest) & kSyncEvents);
    discard_sync_events_ = false;
  }
  last_now_ = now;
  if (!at_least_safeop(state_)) return poll_free_run(now);
  switch (trigger_mode()) {
    case SyncMode::FreeRun: return poll_free_run(now);
    case SyncMode::SmSynchronous:
    case SyncMode::SmSynchronousSm2: return poll_sm(now);
    case SyncMode::DcSync0:
    case SyncMode::DcSync1: return poll_dc(now);
  }
  return {};
}

Nanoseconds SyncController::cycle_time() noexcept {
  const std::uint32_t written = cycle_bytes_ != nullptr  ? load_le<std::uint32_t>(cycle_bytes_)
                                : cycle_slot_ != nullptr ? store_.get<std::uint32_t>(*cycle_slot_)
                                                         : 0;
  const Nanoseconds wanted = written != 0 ? Nanoseconds{written} : kDefaultFreeRunCycle;
  return std::max(wanted, Nanoseconds{limits_.min_cycle_time_ns});
}

SyncPoll SyncController::poll_free_run(Nanoseconds now) noexcept {
  const Nanoseconds cycle = cycle_time();
  if (next_free_run_ && now < *next_free_run_) return {false, next_free_run_};
  next_free_run_ = next_free_run_ ? *next_free_run_ + cycle : now + cycle;
  if (*next_free_run_ <= now) next_free_run_ = now + cycle;
  start_cycle(now);
  return {true, next_free_run_};
}

// A new SM2 buffer shows as a change of SM status bits 5:4 (the 3-buffer
// index last written, Section I §8.1); unlike the AL event bit this works
// whether or not the application consumed the previous buffer.
bool SyncController::new_outputs(Nanoseconds now) noexcept {
  if (!has_outputs_) return false;
  const std::uint8_t status =
      pdi_.read_u8(static_cast<std::uint16_t>(esc::reg::sync_manager(kOutputsSm) + esc::reg::sm::kStatus));
  const auto buffer = static_cast<std::uint8_t>((status & kSmStatusBufferMask) >> kSmStatusBufferShift);
  if (buffer == kNoBufferWritten || (sm2_buffer_ && *sm2_buffer_ == buffer)) return false;
  sm2_buffer_ = buffer;
  if (trace_ != nullptr) trace_->sm_event(kOutputsSm, now);
  return true;
}

bool SyncController::new_input_event() noexcept {
  const bool pending = (events_ & kAlEventSm3) != 0;
  const bool rising = pending && !sm3_event_seen_;
  sm3_event_seen_ = pending;
  return rising;
}

SyncPoll SyncController::poll_sm(Nanoseconds now) noexcept {
  const bool run = has_outputs_ ? new_outputs(now) : new_input_event();
  if (!run) return {};
  if (state_ == AlState::Op && last_outputs_ && now - *last_outputs_ < Nanoseconds{limits_.min_cycle_time_ns}) {
    ++too_small_;
    publish_counters(false);
  }
  last_outputs_ = now;
  if (!has_outputs_ && trace_ != nullptr) trace_->sm_event(3, now);
  start_cycle(now);
  return {true, std::nullopt};
}

SyncPoll SyncController::poll_dc(Nanoseconds now) noexcept {
  if (new_outputs(now)) {
    outputs_since_sync_ = true;
    // Outputs must be in before SYNC0 minus the calc-and-copy time: with
    // none (1C32h:06 = 0, the profile's default) nothing comes too late,
    // and the two DC registers are not read (issue 30: a third of what DC
    // mode added to a cycle).
    const std::uint32_t calc =
        state_ != AlState::Op        ? 0
        : calc_copy_bytes_ != nullptr ? load_le<std::uint32_t>(calc_copy_bytes_)
                                      : store_.get<std::uint32_t>(kSmOutputParameter, syncsub::kCalcAndCopyTime);
    if (calc != 0) {
      std::array<std::uint8_t, 8> b{};
      pdi_.read(dc_register(esc::dcreg::kSystemTime), b);
      const auto sys_now = load_le<std::uint64_t>(b.data());
      pdi_.read(dc_register(esc::dcreg::kStartTimeCyclicOperation), b);
      const auto next_sync0 = load_le<std::uint64_t>(b.data());
      if (next_sync0 > sys_now && next_sync0 - sys_now < calc) {
        ++too_short_;
        publish_counters(false);
      }
    }
  }
  const bool sync1 = trigger_mode() == SyncMode::DcSync1;
  const std::uint32_t bit = sync1 ? esc::dcreg::kAlEventSync1 : esc::dcreg::kAlEventSync0;
  SyncPoll result;
  if ((events_ & bit) != 0) {
    (void)pdi_.read_u8(dc_register(sync1 ? esc::dcreg::kSync1Status : esc::dcreg::kSync0Status));  // acknowledge
    sync_cycle(now);
    start_cycle(now);
    result.run = true;
  }
  // Timeout only once SYNC has started: before the first pulse the start time
  // may lie well ahead, and SafeOp->Op refuses with 0x002D anyway.
  if (sync0_cycle_ != 0 && last_sync_) {
    const Nanoseconds deadline = *last_sync_ + Nanoseconds{std::int64_t{sync0_cycle_} * kSyncTimeoutCycles};
    if (now >= deadline && !timeout_reported_ && esm_ != nullptr) {
      timeout_reported_ = true;
          const bool unit_on = (pdi_.read_u8(dc_register(esc::dcreg::kActivation)) & esc::dcreg::kActivateSyncUnit) != 0;
      const AlStatusCode code =
          unit_on || state_ != AlState::Op ? AlStatusCode::DcSyncTimeoutError : AlStatusCode::FatalSyncError;
      esm_->raise_error(code, AlState::SafeOp);
    }
    result.next = deadline;
  }
  return result;
}

// One SYNC event in DC mode: in SafeOp it counts towards Op; in Op a SYNC
// without new outputs since the previous one is a missed SM event.
void SyncController::sync_cycle(Nanoseconds now) noexcept {
  last_sync_ = now;
  timeout_reported_ = false;
  if (state_ == AlState::SafeOp) ++syncs_in_safeop_;
  if (state_ != AlState::Op) return;
  if (outputs_since_sync_ || !has_outputs_) {
    if (error_counter_ > 0) --error_counter_;
    sync_error_ = false;
  } else {
    ++missed_;
    error_counter_ = static_cast<std::uint16_t>(error_counter_ + kMissPenalty);
    sync_error_ = true;
  }
  outputs_since_sync_ = false;
  publish_counters(false);
  std::uint16_t limit = kDefaultErrorLimit;  // without 10F1h:02
  if (error_limit_bytes_ != nullptr) {
    limit = load_le<std::uint16_t>(error_limit_bytes_);
  } else if (const ObjectStore::Slot* s = store_.slot(kErrorSettings, kErrorSettingsSyncErrorLimit)) {
    limit = store_.get<std::uint16_t>(*s);  // not a plain unsigned: one lookup, not two
  }
  // The sequence is invalid once the counter reaches the limit (Beckhoff's
  // SSC: valid while counter < 10F1h:02; the Yaskawa Sigma-V manual trips at
  // 9 with the limit 9); a limit of 0 switches the detection off (SSC V5.13,
  // the same manual). docs/dc.md "Sync error accounting".
  if (limit != 0 && error_counter_ >= limit && esm_ != nullptr) {
    error_counter_ = 0;
    esm_->raise_error(AlStatusCode::SynchronizationError, AlState::SafeOp);
  }
}

void SyncController::start_cycle(Nanoseconds now) noexcept {
  if (trace_ != nullptr) trace_->app_cycle(true, now);
}

void SyncController::cycle_done(Nanoseconds now) noexcept {
  if (trace_ != nullptr) trace_->app_cycle(false, now);
  // Writing SM3 acknowledged its event: the next one is a new edge even if no
  // poll sees the bit low in between (interrupt-driven firmware).
  if (!has_outputs_) sm3_event_seen_ = (pdi_.read_u32(esc::reg::kAlEventRequest) & kAlEventSm3) != 0;
}

void SyncController::reset_counters() noexcept {
  missed_ = 0;
  too_small_ = 0;
  too_short_ = 0;
  error_counter_ = 0;
  sync_error_ = false;
  publish_counters(true);
}

void SyncController::publish_counters(bool every) noexcept {
  const Published now{missed_, too_small_, too_short_, sync_error_};
  if (!every && now == published_) return;
  for (const std::uint16_t index : {kSmOutputParameter, kSmInputParameter}) {
    if (every || now.missed != published_.missed) (void)store_.set(index, syncsub::kSmEventMissed, missed_);
    if (every || now.too_small != published_.too_small) {
      (void)store_.set(index, syncsub::kCycleTimeTooSmall, too_small_);
    }
    if (every || now.too_short != published_.too_short) {
      (void)store_.set(index, syncsub::kShiftTimeTooShort, too_short_);
    }
    if (every || now.sync_error != published_.sync_error) {
      (void)store_.set(index, syncsub::kSyncError, static_cast<std::uint8_t>(sync_error_ ? 1 : 0));
    }
  }
  published_ = now;
}

}  // namespace ecat::coe
