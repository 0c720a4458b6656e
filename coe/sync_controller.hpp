// The application side of synchronisation (ETG.1000.6 §5.6.7.4.3, ETG.1020):
// keeps 1C32h/1C33h, checks the master's choice at PreOp->SafeOp and
// SafeOp->Op (as an esc::EsmHooks), and decides from the PDI events when the
// application cycle runs:
//   free run (0)        local timer, 1C32h:02 (or the minimum cycle time)
//   SM-synchronous (1)  new SM2 buffer (inputs only: SM3 event)
//   DC SYNC0/SYNC1 (2/3) SYNC0 / SYNC1 event (AL event 0x0220 bit 2/3)
// In Op it counts missed SM events (a SYNC0 without new outputs), cycle time
// too small and shift time too short, and drops the slave to SafeOp on a sync
// error (0x001A), SYNC timeout (0x0034) or a SYNC unit switched off (0x002C).
//
//   coe::SyncController sync(pdi, store, device.sync, has_outputs, has_inputs);
//   sync.install();  sync.attach(esm);
//   each poll: if (sync.poll(now).run) { read outputs, app, write inputs; sync.cycle_done(now); }
// Call poll() before anything reads the SM2 buffer in the same step.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "coe/object_hooks.hpp"
#include "coe/object_store.hpp"
#include "coe/sync_checks.hpp"
#include "coe/sync_mode.hpp"
#include "common/clock.hpp"
#include "esc/dc/vcd_trace.hpp"
#include "esc/esm.hpp"
#include "esc/esm_deferral.hpp"
#include "esc/pdi.hpp"
#include "od/device.hpp"

namespace ecat::coe {

struct SyncPoll {
  bool run = false;                  // start an application cycle now
  std::optional<Nanoseconds> next;   // when poll() next has something to do by time alone
};

class SyncController final : public esc::EsmHooks, public esc::EsmDeferral, public ObjectHooks {
 public:
  // SYNC0 pulses the application must have seen in SafeOp before Op; the
  // SafeOp->Op request stays pending until then, and is refused with 0x002D
  // if they do not come within kSyncWaitTimeout.
  static constexpr unsigned kSyncPulsesBeforeOp = 2;
  static constexpr Nanoseconds kSyncWaitTimeout{2'000'000'000};
  // SYNC missing for this many cycles in SafeOp/Op: 0x0034 (or 0x002C if switched off).
  static constexpr unsigned kSyncTimeoutCycles = 3;
  // Sync error counter (ETG.1020): +3 per missed SM event, -1 per good cycle;
  // at the limit (10F1h:02 if present; 0 = off) the slave leaves Op with 0x001A.
  static constexpr std::uint16_t kMissPenalty = 3;
  static constexpr std::uint16_t kDefaultErrorLimit = 4;
  static constexpr Nanoseconds kDefaultFreeRunCycle{1'000'000};

  SyncController(esc::Pdi& pdi, ObjectStore& store, const od::SyncLimits& limits, bool has_outputs,
                 bool has_inputs) noexcept;

  // Start-up: hooks for 1C32h/1C33h; sub 4 (modes supported) and 5 (minimum
  // cycle) from the limits where the dictionary left them 0.
  void install() noexcept;
  // Registers with the ESM (checks, deferral, state changes) and keeps it for raise_error.
  bool attach(esc::Esm& esm) noexcept;
  void set_trace(esc::VcdProbe* probe) noexcept { trace_ = probe; }

  SyncPoll poll(Nanoseconds now) noexcept;
  // The same with AL event request 0x0220 as the caller read it in this pass
  // (interrupt-driven firmware reads it once and dispatches).
  SyncPoll poll(Nanoseconds now, std::uint32_t al_events) noexcept;
  // AL event request bits that start or prepare a cycle in the current state
  // and mode (SM2/SM3 event, SYNC0/SYNC1), for the AL event mask 0x0204.
  std::uint32_t al_event_mask() const noexcept;
  // The application cycle started by poll() has finished (for the trace).
  void cycle_done(Nanoseconds now) noexcept;

  SyncMode output_mode() const noexcept { return mode_[0]; }
  SyncMode input_mode() const noexcept { return mode_[1]; }
  std::uint16_t sm_events_missed() const noexcept { return missed_; }
  std::uint16_t cycle_time_too_small() const noexcept { return too_small_; }
  std::uint16_t shift_time_too_short() const noexcept { return too_short_; }
  bool sync_error() const noexcept { return sync_error_; }

  // esc::EsmHooks
  esc::AlStatusCode check_transition(esc::AlState from, esc::AlState to) noexcept override;
  void on_state_changed(esc::AlState from, esc::AlState to, esc::AlStatusCode code) noexcept override;
  // esc::EsmDeferral
  bool transition_ready(esc::AlState from, esc::AlState to) noexcept override;
  // ObjectHooks (1C32h/1C33h)
  Expected<void, SdoAbort> on_write(ObjectStore& store, const WriteRequest& request) noexcept override;
  void after_write(ObjectStore& store, std::uint16_t index, std::uint8_t subindex) noexcept override;

 private:
  SyncMode trigger_mode() const noexcept;
  SyncSettings settings() noexcept;
  void load_modes() noexcept;
  bool new_outputs(Nanoseconds now) noexcept;
  bool new_input_event() noexcept;
  SyncPoll poll_free_run(Nanoseconds now) noexcept;
  SyncPoll poll_sm(Nanoseconds now) noexcept;
  SyncPoll poll_dc(Nanoseconds now) noexcept;
  void sync_cycle(Nanoseconds now) noexcept;
  // Writes the counters to 1C32h/1C33h: `every` one, or those that changed
  // since the last call.
  void publish_counters(bool every) noexcept;
  void reset_counters() noexcept;
  void start_cycle(Nanoseconds now) noexcept;
  Nanoseconds cycle_time() noexcept;
  const std::uint8_t* plain_unsigned(const ObjectStore::Slot* s, std::uint32_t bytes) noexcept;

  // What a poll reads every cycle, first and together (issue 30 item 1: at
  // 1000 drives each cache line a drive's cycle touches is a miss; these
  // were spread over three lines).
  esc::VcdProbe* trace_ = nullptr;
  std::optional<Nanoseconds> next_free_run_;
  Nanoseconds last_now_{0};
  const std::uint8_t* cycle_bytes_ = nullptr;  // 1C32h:02's value bytes when it is a plain UNSIGNED32
  std::uint32_t events_ = 0;  // AL event request of the current poll
  od::SyncLimits limits_;
  esc::AlState state_ = esc::AlState::Init;
  std::array<SyncMode, 2> mode_{SyncMode::FreeRun, SyncMode::FreeRun};  // [0] 1C32h, [1] 1C33h
  bool has_outputs_;
  // Set at PreOp->SafeOp: the SYNC bits of the AL event snapshot the firmware
  // took before the transition may be stale pulses; the next poll re-reads them.
  bool discard_sync_events_ = false;

  esc::Pdi& pdi_;
  ObjectStore& store_;
  bool has_inputs_;
  esc::Esm* esm_ = nullptr;
  std::array<bool, 2> mode_written_{};
  std::uint32_t sync0_cycle_ = 0;  // 0x09A0 at PreOp->SafeOp
  std::optional<std::uint8_t> sm2_buffer_;  // last seen SM2 status bits 5:4
  bool sm3_event_seen_ = false;
  bool outputs_since_sync_ = false;
  std::optional<Nanoseconds> last_outputs_;
  std::optional<Nanoseconds> last_sync_;
  unsigned syncs_in_safeop_ = 0;
  std::uint16_t error_counter_ = 0;
  std::uint16_t missed_ = 0;
  std::uint16_t too_small_ = 0;
  std::uint16_t too_short_ = 0;
  bool sync_error_ = false;
  bool timeout_reported_ = false;
  const ObjectStore::Slot* cycle_slot_ = nullptr;  // 1C32h:02, found once at install()
  // 10F1h:02 and 1C32h:06's value bytes when plain (plain_unsigned, found
  // once at install()): read in place each DC cycle; otherwise through the store.
  const std::uint8_t* error_limit_bytes_ = nullptr;
  const std::uint8_t* calc_copy_bytes_ = nullptr;
  // The counters as publish_counters last wrote them: it writes only what
  // changed, as each write moves the store's generation and a drive's
  // binding then reads every entry again (issue 30: in DC mode every SYNC
  // cycle did, 2,500 instructions a drive).
  struct Published {
    std::uint16_t missed = 0;
    std::uint16_t too_small = 0;
    std::uint16_t too_short = 0;
    bool sync_error = false;
    bool operator==(const Published&) const = default;
  };
  Published published_;
  std::optional<Nanoseconds> op_wait_start_;
};

}  // namespace ecat::coe
