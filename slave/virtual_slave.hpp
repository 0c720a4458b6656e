// One virtual EtherCAT slave: the emulated ESC (silicon) and the firmware
// above its PDI - the EtherCAT state machine, the mailbox with CoE, and, for
// a CiA402 device, the drive with its simulated motor. Built from one device
// description, which it holds, so the dictionary it serves is the one the
// ESI and SII were made from (STYLE lesson 2: no globals, one object each).
// The description is read-only once the slave is built (the values live in
// the CoE object store), so slaves of one device type may share it
// (issue 16: a chain of thousands of slaves keeps one copy).
#pragma once

#include <algorithm>
#include <memory>
#include <optional>
#include <string>

#include "common/clock.hpp"
#include "common/expected.hpp"
#include "esc/esc.hpp"
#include "od/device.hpp"
#include "pdi_spi/emulated_chip.hpp"
#include "pdi_spi/spi_pdi.hpp"
#include "slave/detached_pdi.hpp"
#include "slave/firmware.hpp"
#include "slave/slave_options.hpp"
#include "slave/slave_stats.hpp"

namespace ecat::slave {

class alignas(64) VirtualSlave {  // one cache line for the hot members below
 public:
  // Fails with a message when the description cannot be served (e.g. its
  // SII image does not fit the EEPROM, or the parameter file is unusable).
  static Expected<std::unique_ptr<VirtualSlave>, std::string> create(od::DeviceDescription device,
                                                                     const Clock& clock,
                                                                     const SlaveOptions& options);
  // The same over a description shared with other slaves (not null), its
  // ESC's memory block at `esc_memory_colour` (esc::EscConfig::memory_colour:
  // slave::Chain gives its position).
  static Expected<std::unique_ptr<VirtualSlave>, std::string> create(
      std::shared_ptr<const od::DeviceDescription> device, const Clock& clock, const SlaveOptions& options,
      std::uint8_t esc_memory_colour = 0);
  ~VirtualSlave();
  VirtualSlave(const VirtualSlave&) = delete;
  VirtualSlave& operator=(const VirtualSlave&) = delete;

  esc::Esc& esc() noexcept { return *esc_; }
  const esc::Esc& esc() const noexcept { return *esc_; }
  const od::DeviceDescription& device() const noexcept { return *device_; }
  Firmware& firmware() noexcept { return *firmware_; }
  const Firmware& firmware() const noexcept { return *firmware_; }
  // SlaveOptions::name as created (ecat-slave: the topology name or "slave-N").
  const std::string& name() const noexcept { return options_.name; }
  // The SPI backend the firmware runs over (PdiKind::Lan9252/Et1100Spi),
  // nullptr for the direct PDI; and the emulated chip it talks to.
  pdi_spi::SpiPdi* spi_pdi() noexcept { return spi_pdi_.get(); }
  const pdi_spi::EmulatedChip* spi_chip() const noexcept { return chip_.get(); }

  // What the firmware's host sees without a PDI access: the ESC's IRQ (or
  // the emulated chip's IRQ pin) and the AL event mask the ESC holds.
  EscLines lines() const noexcept {
    return {chip_ ? chip_->irq_pin() : esc_->irq(), load_le<std::uint32_t>(esc_->memory() + esc::reg::kAlEventMask)};
  }
  // Attaches the firmware and the ESC's DC unit to a VCD probe.
  void attach_trace(esc::VcdProbe& probe) noexcept;

  // Runs the ESC's timers up to `now`, then the firmware (ESM, mailbox,
  // process data, drive cycle) if the ESC raised its IRQ or the firmware's
  // deadline came. Call at the deadline it returns. Returns when it next
  // needs to run.
  std::optional<Nanoseconds> poll(Nanoseconds now) noexcept { return deadline_or_none(advance(now)); }
  // The same as a time, kNoDeadline when none (slave::Chain's form).
  Nanoseconds advance(Nanoseconds now) noexcept;

  // After a frame passed this slave's ESC at `now`: the ESC's timers if one
  // is due, then the firmware if the ESC raised its IRQ or its deadline came.
  void after_frame(Nanoseconds now) noexcept;
  // Whether after_frame(now) may have anything to do: a few loads, so a
  // chain asks every slave after every frame cheaply (issue 8).
  bool after_frame_due(Nanoseconds now) const noexcept { return now >= wake_at() || pending(); }
  // after_frame_due's two halves: when time alone makes it due (the ESC's
  // or the firmware's deadline as the last poll left it), and whether it is
  // due whatever the time (IRQ, work finished pass by pass). Both change only
  // when the ESC is entered by a frame or the slave is polled (slave::Chain).
  Nanoseconds wake_at() const noexcept {
    return has_firmware_ ? std::min(esc_wake_, fw_due_.wake) : esc_wake_;
  }
  // Firmware::pending, answered from fw_due_ (where the firmware keeps it).
  bool pending() const noexcept { return has_firmware_ && fw_due_.pending(lines()); }
  // What poll() would return now if nothing is due (Nanoseconds::max():
  // nothing armed): the ESC's timers as they stand after whatever accessed
  // it since the last poll (esc::Esc::wake_bound: the watchdogs and the SII
  // exactly, DC its last deadline or, after a DC write, "now"), and the
  // firmware's deadline. A poll before it only notes the time, unless the
  // slave is pending().
  Nanoseconds next_deadline() const noexcept {
    const Nanoseconds esc = esc_->wake_bound();
    return has_firmware_ ? std::min(esc, fw_due_.wake) : esc;
  }
  // When a chain next has to visit this slave by time alone: next_deadline(),
  // or earlier the ESC deadline the last poll left (wake_at), which
  // after_frame() goes by - a poll there refreshes it, as a poll of every
  // slave would (slave::Chain::poll).
  Nanoseconds visit_at() const noexcept { return std::min(esc_wake_, next_deadline()); }

  SlaveStatus status() const noexcept;

  // Whether its firmware touches nothing outside this slave, so that it may
  // run on any thread beside other slaves' (slave::Chain's firmware lanes):
  // not with a VCD probe (one file for the chain), an external firmware, an
  // SPI PDI (a chip or bus the host may share), or an EoE report callback.
  bool runs_apart() const noexcept {
    return probe_ == nullptr && !detached_ && !spi_pdi_ && (options_.eoe_init.empty() || !options_.report);
  }

  // Power-on again after a power cut (slave::FaultCatalogue's power_cycle):
  // the ESC back to its power-up register values with the SII loaded from
  // its EEPROM, the firmware started afresh (Init, the dictionary's
  // defaults and the stored parameters, as at start-up). Invalidates the
  // Firmware, its ESM and application handed out before. With an SPI PDI the
  // emulated chip powers up too (a new LAN9252 / ET1100 SPI slave, the
  // firmware's bring-up over SPI again), and spi_pdi()/spi_chip() change.
  Expected<void, std::string> power_on();

  // Clean shutdown: nothing is lost (stored parameters are already on disk;
  // this flushes traces).
  void shutdown() noexcept;

 private:
  // The firmware's run at `now`, its accesses to the ESC at one time
  // (esc::Esc::pin_pdi_time): one read of a live run's clock, not one per access.
  Nanoseconds run_firmware(Nanoseconds now) noexcept;
  VirtualSlave() = default;
  // The emulated SPI chip on esc_ and the firmware's SPI backend to it
  // (options_.pdi Lan9252/Et1100Spi), brought up as at power-on.
  Expected<void, std::string> make_spi_pdi();

  // What the chain reads after every frame and in every poll first, on one
  // cache line (the object is 64-byte aligned and these are 49 bytes): at
  // 1000 slaves each is a last-level miss per visit (docs/performance-log.md
  // "Session 14"); the firmware's part of the check is kept here too
  // (fw_due_, Firmware::keep_due_in), so a slave with nothing due is
  // answered from this line and the ESC's IRQ and mask.
  std::unique_ptr<esc::Esc> esc_;
  std::unique_ptr<Firmware> firmware_;
  std::unique_ptr<pdi_spi::EmulatedChip> chip_;  // SPI PDI only
  Nanoseconds esc_wake_ = Nanoseconds::max();  // the ESC's next deadline at the last poll, max when none
  Firmware::Due fw_due_;  // written by *firmware_
  // False for an ESC without PDI (SII word 0 PDI type 0 and no mailbox SM,
  // od::runs_firmware; e.g. a coupler or junction): no µC, the firmware
  // never runs; with device emulation
  // (0x0141 bit 0) the ESC itself copies AL control into AL status.
  bool has_firmware_ = true;
  std::shared_ptr<const od::DeviceDescription> device_;
  std::unique_ptr<pdi_spi::SpiPdi> spi_pdi_;      // SPI PDI only
  SlaveOptions options_;                 // as created, for power_on()
  esc::VcdProbe* probe_ = nullptr;       // attach_trace's, for power_on()
  std::unique_ptr<DetachedPdi> detached_;
};

}  // namespace ecat::slave
