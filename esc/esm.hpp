// The EtherCAT state machine as application firmware runs it (ETG.1000.6
// §6.4; SOES ESC_state): poll() takes the master's request from AL control
// 0x0120 (signalled by AL event 0x0220 bit 0), checks it against the
// transition table, the sync manager configuration and the registered hooks,
// and answers in AL status 0x0130 / AL status code 0x0134 - all through the
// PDI, so the same code would drive a real ESC.
//
//   esc::Esm esm(pdi, config);
//   esm.add_hooks(coe_checks);   // e.g. PDO sizes vs SM2/SM3
//   esm.reset();                 // Init, no error, SMs deactivated
//   for (;;) { ...; esm.poll(); }
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "esc/al_status_code.hpp"
#include "esc/esm_config.hpp"
#include "esc/esm_deferral.hpp"
#include "esc/esm_hooks.hpp"
#include "esc/esm_transition.hpp"
#include "esc/pdi.hpp"

namespace ecat::esc {

// AL control 0x0120 / AL status 0x0130 bits (ESC datasheet Section II 0x0120).
inline constexpr std::uint16_t kAlStateMask = 0x000F;
inline constexpr std::uint16_t kAlErrorAck = 0x0010;          // control bit 4
inline constexpr std::uint16_t kAlErrorIndication = 0x0010;   // status bit 4
inline constexpr std::uint16_t kAlIdRequest = 0x0020;         // control bit 5
inline constexpr std::uint16_t kAlIdLoaded = 0x0020;          // status bit 5
// AL event request 0x0220 bits the state machine consumes.
inline constexpr std::uint32_t kAlEventAlControl = 1u << 0;
inline constexpr std::uint32_t kAlEventSmActivation = 1u << 4;
inline constexpr std::uint32_t kAlEventWatchdog = 1u << 6;
// Process-data watchdog status 0x0440 bit 0: 0 = expired.
inline constexpr std::uint16_t kWatchdogProcessDataActive = 0x0001;

class Esm {
 public:
  static constexpr std::size_t kMaxHooks = 8;

  Esm(Pdi& pdi, const EsmConfig& config) noexcept;

  // Registers a participant; false if kMaxHooks are already registered.
  // Hooks are asked in registration order; the first refusal wins.
  bool add_hooks(EsmHooks& hooks) noexcept;
  // Unregisters a participant added by add_hooks (the others keep their
  // order); false if it was not registered. For participants that come and
  // go at run time (slave::FaultCatalogue).
  bool remove_hooks(EsmHooks& hooks) noexcept;
  // Registers a participant that can hold an upward transition pending;
  // false if kMaxHooks are already registered.
  bool add_deferral(EsmDeferral& deferral) noexcept;

  // Power-on state: Init, code 0, all four SMs deactivated from the PDI.
  void reset() noexcept;

  // Handles a pending AL control request, a SM change by the master and the
  // process-data watchdog. Call once per application cycle.
  void poll() noexcept;
  // The same for firmware driven by the ESC's interrupt (SOES/SSC
  // AL_Event handling): `events` is AL event request 0x0220 as the caller
  // read it once; the watchdog status is read only when bit 6 says it
  // expired, and a transition held by a deferral is retried.
  void poll(std::uint32_t events) noexcept;
  // AL event request bits poll(events) acts on (for the AL event mask 0x0204).
  static constexpr std::uint32_t kEventsHandled = kAlEventAlControl | kAlEventSmActivation | kAlEventWatchdog;

  // Local error (ETG.1000.6 §6.4.1.3): the slave drops to `target` (never
  // up) with ErrInd and `code`, e.g. sync loss -> SafeOp + 0x001A.
  void raise_error(AlStatusCode code, AlState target) noexcept;

  AlState state() const noexcept { return state_; }
  bool error_indicated() const noexcept { return error_; }
  AlStatusCode status_code() const noexcept { return code_; }
  // The requested state while a transition waits for a deferral.
  std::optional<AlState> pending() const noexcept { return pending_; }

 private:
  void handle_request(std::uint16_t control) noexcept;
  void carry_out(AlState target, std::uint16_t control) noexcept;
  void retry_pending() noexcept;
  bool deferrals_ready(AlState from, AlState to) noexcept;
  void handle_sm_change() noexcept;
  void handle_events(std::uint32_t events, bool watchdog_polled) noexcept;
  void handle_watchdog(std::uint32_t events, bool polled) noexcept;
  AlStatusCode check(EsmTransition t, AlState from, AlState to) noexcept;
  AlStatusCode ask_hooks(AlState from, AlState to) noexcept;
  void enter(AlState to, AlStatusCode code, bool error) noexcept;
  void refuse(AlStatusCode code) noexcept;
  void apply_services(AlState s) noexcept;
  void update_identification(std::uint16_t control, AlState target) noexcept;
  void write_status() noexcept;

  Pdi& pdi_;
  EsmConfig config_;
  std::array<EsmHooks*, kMaxHooks> hooks_{};
  std::size_t hook_count_ = 0;
  std::array<EsmDeferral*, kMaxHooks> deferrals_{};
  std::size_t deferral_count_ = 0;
  std::optional<AlState> pending_;
  std::uint16_t pending_control_ = 0;
  AlState state_ = AlState::Init;
  bool error_ = false;
  AlStatusCode code_ = AlStatusCode::NoError;
  std::uint16_t id_value_ = 0;  // non-zero while 0x0134 shows the device ID
};

}  // namespace ecat::esc
