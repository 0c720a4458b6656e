// How one virtual slave is set up beyond its device description.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "coe/eoe_server.hpp"
#include "coe/storage_quota.hpp"
#include "common/clock.hpp"
#include "esc/inner_delay_figures.hpp"
#include "pdi_spi/lan9252_pdi.hpp"
#include "slave/eoe_init_check.hpp"

namespace ecat::slave {

// Which PDI the firmware reaches its (emulated) ESC through: the ESC's own
// esc::Pdi, or SPI framing to an emulated LAN9252 or ET1100 SPI slave
// (pdi_spi/), byte-exact as on a real chip (docs/real-esc.md).
enum class PdiKind : std::uint8_t { Direct, Lan9252, Et1100Spi };

struct SlaveOptions {
  // Where stored parameters (1010h) and FoE files live; empty: nothing is
  // persisted (parameters are still kept for the life of the process).
  std::filesystem::path state_dir;
  // What may be written there, shared by every slave that uses state_dir
  // (ecat-slave makes one for the chain). Null: the slave makes its own with
  // the default limits (64 MiB, 1024 files) over what state_dir holds.
  std::shared_ptr<coe::StorageQuota> state_quota;
  // Name of this slave's files inside state_dir ("slave-1"); chains number them.
  std::string name = "slave";
  // Password FoE read/write requests must carry (0: none; coe::FoeServer).
  std::uint32_t foe_password = 0;
  // BUSY replies to each FoE read/write request before it is served, as a
  // slave whose file is not ready at once (0: never; coe::FoeServer).
  std::uint16_t foe_busy = 0;
  // Oscillator error of the DC local clock and its value at time 0.
  double clock_ppm = 0.0;
  std::uint64_t clock_start = 0;
  // Keep a per-cycle motion trace of the drive (for --plot).
  bool motion_trace = false;
  PdiKind pdi = PdiKind::Direct;
  // The firmware runs outside, in another process attached to the ESC's PDI
  // (ecat-slave --pdi-host, docs/pdi-host.md): the built-in firmware never
  // touches this ESC (it is built over a detached PDI, so the control
  // interface still finds a dictionary), and the ESC behaves as silicon
  // whose µC is whatever the other process does.
  bool external_firmware = false;
  pdi_spi::Lan9252Options lan9252{};  // with PdiKind::Lan9252
  // Time a frame spends inside this slave's ESC (esc::EscConfig
  // processing_delay / forwarding_delay; docs/esc.md "Forwarding delays
  // inside an ESC"); unset: the default of the device's ESC type and port
  // types from delay_figures. forwarding_delay, when set, applies to every
  // port 1..3 (it replaces the per-port defaults).
  std::optional<Nanoseconds> processing_delay;
  std::optional<Nanoseconds> forwarding_delay;
  // The per-ESC-type figures the defaults come from (docs/esc.md "Forwarding
  // delay figures per ESC type"); a test may give its own table.
  std::span<const esc::InnerDelayFigures> delay_figures = esc::datasheet_inner_delays();
  // EoE start-up IP parameters, for a device that lists EoE (docs/eoe.md).
  coe::eoe::IpParameters eoe = coe::eoe::default_parameters();
  // The ENI's EoE InitCmds for this slave (ecat-slave --eni): checked each
  // time the slave enters their state, the line handed to `report`
  // (slave/eoe_init_check.hpp, docs/eoe.md "ENI EoE InitCmds").
  std::vector<EoeInitExpectation> eoe_init;
  std::function<void(const std::string&)> report;
};

}  // namespace ecat::slave
