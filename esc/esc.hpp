// The emulated EtherCAT Slave Controller: a datagram processor over a 64 KiB
// register file + process RAM (ESC datasheet Section I/II; ETG.1000.4 §5-6;
// shared/spec/esc-registers.md). The EtherCAT side is process(): the frame's
// datagrams as they pass this ESC. The application side is the esc::Pdi
// interface (read/write with the sync-manager buffer rules), exactly what a
// µC sees on a real ESC. Time comes from the injected clock (PDI side) or is
// passed in per frame / poll; nothing here sleeps or reads the system clock.
//
// Behaviour follows an ET1100 wherever the datasheet leaves a choice
// (docs/esc.md lists every register and every such choice).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>

#include "common/clock.hpp"
#include "common/frame_parser.hpp"
#include "esc/access_side.hpp"
#include "esc/dc/dc_unit.hpp"
#include "esc/esc_config.hpp"
#include "esc/fmmu.hpp"
#include "esc/pdi.hpp"
#include "esc/register_bits.hpp"
#include "esc/sii_interface.hpp"
#include "esc/sync_manager.hpp"
#include "esc/watchdog.hpp"

namespace ecat::esc {

inline constexpr std::size_t kAddressSpace = 0x10000;

class Esc final : public Pdi {
 public:
  // `clock` times PDI accesses (watchdog, DC); it must outlive the Esc.
  Esc(EscConfig config, const Clock& clock);
  Esc(const Esc&) = delete;
  Esc& operator=(const Esc&) = delete;
  ~Esc() override;

  // --- Pdi (application side) ---
  void read(std::uint16_t address, std::span<std::uint8_t> out) noexcept override;
  void write(std::uint16_t address, std::span<const std::uint8_t> in) noexcept override;

  // --- EtherCAT side ---
  // Processes every datagram of a validated frame as it passes this ESC at
  // time `now`: addressing, data, WKC, ADP, IRQ. Returns false if the ESC
  // destroyed the frame (circulating-frame prevention, Section I §3.5.1:
  // a frame passing a closed port 0 a second time).
  bool process(const FrameView& frame, Nanoseconds now) noexcept;
  // A frame that arrived broken: counts it in the RX error counters
  // (0x0300 invalid frame on `port`, or 0x0308 when an upstream ESC already
  // marked it) and otherwise leaves the ESC unchanged.
  void count_rx_error(unsigned port, bool forwarded) noexcept;
  // Runs the time-driven parts (watchdogs, SII busy, DC) up to `now`;
  // returns the next time it needs to run, if any.
  std::optional<Nanoseconds> poll(Nanoseconds now) noexcept;

  // Hardware reset (power-on or the 0x0040/0x0041 'R','E','S' sequence):
  // registers to reset values, EEPROM load from the SII image.
  void reset() noexcept;

  // --- Ports (set by esc::Segment) ---
  // Physical link on `port` (0..3): a neighbour is connected. Unconnected
  // ports are closed (looped back) as an ET1100 in Auto loop mode does.
  void set_link(unsigned port, bool link) noexcept;
  bool link(unsigned port) const noexcept;
  // Whether a frame leaving the processing unit toward `port` goes out
  // (open) or is looped back (closed), per link and DL control loop bits.
  bool port_open(unsigned port) const noexcept;

  // --- Accessors for tests and the slave layer ---
  const std::uint8_t* memory() const noexcept { return mem_.get(); }
  // Raw little-endian register value without side effects (the DC block is
  // read through DcUnit as a PDI read).
  std::uint16_t register_u16(std::uint16_t address) const noexcept;
  const EscConfig& config() const noexcept { return config_; }
  DcUnit& dc() noexcept { return dc_; }
  const SyncManager& sync_manager(unsigned n) const noexcept { return sms_[n]; }
  // True when (AL event request & AL event mask) != 0: the IRQ pin to the µC.
  bool irq() const noexcept;
  // Time of the latest access: frame, PDI access or poll.
  Nanoseconds last_time() const noexcept { return now_; }

 private:
  // Register space 0x0000-0x0FFF from either side (esc/register_access.cpp).
  // Return true if the access counts for the WKC.
  bool reg_read(std::uint16_t address, std::span<std::uint8_t> out, Side side) noexcept;
  bool reg_write(std::uint16_t address, std::span<const std::uint8_t> in, Side side) noexcept;
  std::uint8_t reg_read_byte(std::uint16_t address, Side side) noexcept;
  bool reg_write_byte(std::uint16_t address, std::uint8_t value, Side side) noexcept;
  void after_register_write(std::uint16_t address, std::uint8_t old_value, Side side) noexcept;

  // Whole address space through the sync managers (esc/memory_access.cpp).
  // Return true if at least one byte was accessible (WKC rule, ETG.1000.4 §5.4.3).
  bool mem_read(std::uint16_t address, std::span<std::uint8_t> out, Side side) noexcept;
  bool mem_write(std::uint16_t address, std::span<const std::uint8_t> in, Side side) noexcept;
  // Raw copy without side effects (bit-wise FMMU writes start from it).
  void peek(std::uint32_t address, std::span<std::uint8_t> out) const noexcept;

  // Datagram engine (esc/datagram_engine.cpp).
  void process_datagram(DatagramView d) noexcept;
  std::uint16_t process_logical(DatagramView d) noexcept;
  bool addressed_configured(std::uint16_t adp) const noexcept;

  // Events (esc/esc.cpp).
  std::uint32_t al_event() const noexcept;
  std::uint16_t ecat_event() const noexcept;
  void set_al_event(std::uint32_t bits) noexcept;
  void clear_al_event(std::uint32_t bits) noexcept;
  void set_ecat_event(std::uint16_t bits) noexcept;
  void clear_ecat_event(std::uint16_t bits) noexcept;
  void apply(unsigned sm, const SmSignals& sig) noexcept;
  std::uint16_t irq_field() const noexcept;
  void update_dl_status() noexcept;
  void load_eeprom(bool power_on) noexcept;
  void run_timers(Nanoseconds now) noexcept;
  void pdi_watchdog_trigger(Nanoseconds t) noexcept;
  void sii_action(SiiInterface::Action a) noexcept;
  std::uint32_t dl_control() const noexcept;
  std::uint32_t ram_end() const noexcept;

  EscConfig config_;
  const Clock& clock_;
  std::unique_ptr<std::uint8_t[]> mem_;  // kAddressSpace bytes, allocated once
  std::array<SyncManager, kMaxSyncManagers> sms_{};
  std::array<Fmmu, kMaxFmmus> fmmus_{};
  std::array<bool, kMaxPorts> link_{};
  DcUnit dc_;
  SiiInterface sii_;
  Watchdogs watchdogs_;
  Nanoseconds now_{0};
  // Per-frame state: write-protection release (0x0020/0x0030 written this frame).
  bool register_write_enabled_ = false;
  bool esc_write_enabled_ = false;
  // ESC reset sequence progress for 0x0040 (ECAT) and 0x0041 (PDI).
  std::array<std::uint8_t, 2> reset_step_{};
  bool reset_requested_ = false;
  // AL control written by ECAT and not yet read by the PDI (Section II 0x0120).
  bool al_control_pending_ = false;
};

}  // namespace ecat::esc
