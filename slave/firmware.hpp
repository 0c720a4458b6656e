// What runs above the PDI of one virtual slave, as the firmware of a real
// slave would: the EtherCAT state machine, the CoE server (mailbox, SDO,
// PDOs, parameters), the synchronisation logic that decides when the
// application cycle runs, and the application itself (a CiA402 drive when
// the device is one). Built once; poll() allocates nothing.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "coe/coe_server.hpp"
#include "coe/sync_controller.hpp"
#include "common/cache_line.hpp"
#include "common/clock.hpp"
#include "common/le.hpp"
#include "esc/dc/vcd_trace.hpp"
#include "esc/esm.hpp"
#include "esc/pdi.hpp"
#include "esc/registers.hpp"
#include "od/device.hpp"
#include "slave/application.hpp"
#include "slave/slave_options.hpp"
#include "slave/slave_stats.hpp"

namespace ecat::slave {

// What the firmware's host sees of the ESC without a PDI access: the IRQ
// pin to the µC and the AL event mask 0x0204 the ESC holds (an ESC reset
// clears it; the firmware then programs it again). The emulated slave
// reads both from esc::Esc (a few loads); a host on a real chip passes its
// interrupt line and the mask the firmware programmed.
struct EscLines {
  bool irq = false;
  std::uint32_t al_event_mask = 0;
};

class Firmware {
 public:
  // What a chain checks of a sleeping firmware after every frame
  // (may_want_poll's own part): the time it next has to run by, the AL
  // event mask it last programmed and whether work waits that it finishes
  // pass by pass. Kept where keep_due_in() put it - by a VirtualSlave on its
  // own hot cache line, so the check does not read this object at all
  // (docs/performance-log.md "Session 15: the skip index...").
  struct Due {
    Nanoseconds wake = Nanoseconds::max();  // the deadline poll() last returned, max when none
    std::uint32_t event_mask = 0;
    bool pass_work = true;
    // The ESC no longer holds the mask programmed (an ESC reset clears it).
    bool mask_lost(EscLines lines) const noexcept { return lines.al_event_mask != event_mask; }
    // Due whatever the time: the IRQ, work finished pass by pass, a lost mask.
    bool pending(EscLines lines) const noexcept { return lines.irq || pass_work || mask_lost(lines); }
  };

  // Runs above any esc::Pdi: the emulated ESC itself, or an SPI backend
  // to a real (or emulated) LAN9252/ET1100 (pdi_spi/).
  Firmware(esc::Pdi& pdi, const od::DeviceDescription& device, const SlaveOptions& options);
  Firmware(const Firmware&) = delete;
  Firmware& operator=(const Firmware&) = delete;
  // The application refers to coe_: it goes first, as when app_ was declared
  // after coe_ (it now sits with the members each frame reads).
  ~Firmware() { app_.reset(); }

  // One pass of the firmware at `now`, as an interrupt handler plus main
  // loop of SSC/SOES: AL event request 0x0220 is read once and dispatched
  // (ESM, mailbox, synchronisation, application cycle; in DC mode the ESM
  // and the synchronisation read it again, see firmware.cpp); the AL event mask
  // 0x0204 is kept to what this pass found the firmware needs. Returns when
  // it next needs to run by time alone.
  std::optional<Nanoseconds> poll(Nanoseconds now, EscLines lines) noexcept {
    return deadline_or_none(advance(now, lines));
  }
  // poll() with its answer as a time, kNoDeadline when nothing is armed
  // (the chain's form: no optional returned through a call, common/clock.hpp).
  Nanoseconds advance(Nanoseconds now, EscLines lines) noexcept;

  // Whether a frame that just passed the ESC gives the firmware work at
  // `now`: the ESC's IRQ (AL event request & mask), a deadline due, or
  // something it finishes pass by pass (a transition waiting for a
  // deferral, a mailbox reply waiting for SM1, an SM whose event the master
  // switched off so the firmware has to look by itself).
  bool wants_poll(Nanoseconds now, EscLines lines) const noexcept {
    return lines.irq || poll_each_frame_ || due_->wake <= now || esm_.pending() || mailbox_output() ||
           mask_lost(lines);
  }
  // A cheap superset of wants_poll() for the check after every frame of a
  // chain (issue 8): the IRQ and a lost mask as they are now, the deadline
  // and the pass-by-pass work as the last poll() left them - they change
  // only in poll() (the firmware's own state) or by time.
  bool may_want_poll(Nanoseconds now, EscLines lines) const noexcept {
    return now >= wake_time() || pending(lines);
  }
  // may_want_poll's two halves (issue 16 item 5: a chain keeps them per
  // slave and asks only the slaves a frame entered, the pending ones and
  // the ones whose time came): the time alone, and what does not wait for it.
  Nanoseconds wake_time() const noexcept { return due_->wake; }
  // Work arrived from outside the ESC (an EoE frame from a TAP): look at the
  // next frame even without an IRQ.
  void wake() noexcept { due_->pass_work = true; }
  bool pending(EscLines lines) const noexcept { return due_->pending(lines); }
  // The time poll() last asked to run again at.
  std::optional<Nanoseconds> next_deadline() const noexcept {
    return due_->wake == Nanoseconds::max() ? std::nullopt : std::optional<Nanoseconds>(due_->wake);
  }
  // The AL event mask the firmware last programmed.
  std::uint32_t event_mask() const noexcept { return due_->event_mask; }
  // Keeps the Due values in *due from now on (copied there first; `due`
  // must outlive this firmware), instead of in this object.
  void keep_due_in(Due* due) noexcept {
    *due = *due_;
    due_ = due;
  }

  esc::Esm& esm() noexcept { return esm_; }
  coe::CoeServer& coe() noexcept { return coe_; }
  const coe::CoeServer& coe() const noexcept { return coe_; }
  coe::SyncController& sync() noexcept { return sync_; }
  Application* application() noexcept { return app_.get(); }
  // Replaces the application the device description chose (the CiA402 drive,
  // or none) with the caller's own, e.g. a digital I/O terminal
  // (examples/dio16-slave). Set-up only: before the master leaves Init.
  void set_application(std::unique_ptr<Application> app) noexcept { app_ = std::move(app); }
  // Hands the application over (a test wraps it in a misbehaving one).
  std::unique_ptr<Application> take_application() noexcept { return std::move(app_); }
  const std::vector<std::string>& warnings() const noexcept { return coe_.warnings(); }
  // Each check of the ENI's EoE InitCmds so far, in order (SlaveOptions::eoe_init).
  const std::vector<EoeInitResult>& eoe_init_results() const noexcept { return eoe_init_results_; }

  // The firmware's part of a VCD trace (ESM states, SM events, cycles);
  // the ESC's DC unit is attached by the host that owns the ESC.
  void attach_trace(esc::VcdProbe& probe) noexcept;
  // Counters of the firmware; watchdog_expiries is the host's to fill (the
  // ESC counts them in 0x0442).
  SlaveStatus status() const noexcept;

 private:
  void application_cycle(Nanoseconds now) noexcept;
  void program_event_mask(bool sms_changed, EscLines lines) noexcept;
  bool mask_lost(EscLines lines) const noexcept { return due_->mask_lost(lines); }
  void note_al_status_code(Nanoseconds now) noexcept;
  void check_eoe_init(esc::AlState entered) noexcept;
  bool sm_events_enabled(std::uint32_t mask) noexcept;
  // coe::MailboxServer::has_output(), asked only when the flag the server
  // keeps here (keep_idle_flag) does not already say no.
  bool mailbox_output() const noexcept { return !mailbox_idle_ && coe_.mailbox().has_output(); }

  esc::Pdi& pdi_;
  // What the chain asks after every frame and poll() keeps, first and
  // together (one or two cache lines, not one per member spread behind the
  // CoE server's kilobytes): at 1000 slaves each line is a last-level miss
  // per visit (docs/performance-log.md "Session 14").
  // For may_want_poll(): where the Due values are (own_due_ or the host's).
  Due* due_ = &own_due_;
  std::optional<Nanoseconds> last_cycle_;
  esc::AlStatusCode code_seen_ = esc::AlStatusCode::NoError;  // the last one put into 10F3h
  esc::AlState state_seen_ = esc::AlState::Init;
  bool poll_each_frame_ = false;
  bool mailbox_idle_ = false;  // set by coe_.mailbox() (MailboxServer::keep_idle_flag)
  std::uint64_t cycles_ = 0;
  std::uint64_t polls_ = 0;
  std::unique_ptr<Application> app_;  // its cycle is called every cycle
  Due own_due_;  // until keep_due_in()
  esc::Esm esm_;
  std::shared_ptr<coe::StorageQuota> state_quota_;  // before coe_, which points at it
  coe::CoeServer coe_;
  // From a cache line's start, as the object itself (alignas makes it start
  // one): its per-poll members come first (session 29), and where they fall
  // no longer follows the CoE server's size - 16 bytes less there put them
  // across another line and made the 1000-drive cycle 1.04-1.07x slower
  // (docs/performance-log.md "Session 30").
  alignas(kCacheLineBytes) coe::SyncController sync_;
  esc::VcdProbe* trace_ = nullptr;
  std::vector<EoeInitExpectation> eoe_init_;
  std::function<void(const std::string&)> report_;
  std::vector<EoeInitResult> eoe_init_results_;
};

}  // namespace ecat::slave
