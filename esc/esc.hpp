// The emulated EtherCAT Slave Controller: a datagram processor over the
// register file 0x0000-0x0FFF + the configured process RAM (ESC datasheet Section I/II; ETG.1000.4 §5-6;
// shared/spec/esc-registers.md). The EtherCAT side is process(): the frame's
// datagrams as they pass this ESC. The application side is the esc::Pdi
// interface (read/write with the sync-manager buffer rules), exactly what a
// µC sees on a real ESC. Time comes from the injected clock (PDI side) or is
// passed in per frame / poll; nothing here sleeps or reads the system clock.
//
// Behaviour follows an ET1100 wherever the datasheet leaves a choice
// (docs/esc.md lists every register and every such choice).
//
// Speed (issue 8): a frame is walked in place; what a frame needs per ESC
// is cached and recomputed only when its registers change (port loop state,
// enabled SMs, active FMMUs, the next timer deadline), and register bytes
// without side effects are copied as a block (esc/register_map.hpp).
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <utility>

#include "common/clock.hpp"
#include "common/frame_parser.hpp"
#include "esc/access_side.hpp"
#include "esc/dc/dc_unit.hpp"
#include "esc/esc_config.hpp"
#include "esc/fmmu.hpp"
#include "esc/pass_hook.hpp"
#include "esc/pdi.hpp"
#include "esc/register_bits.hpp"
#include "esc/registers.hpp"
#include "esc/sii_interface.hpp"
#include "esc/sync_manager.hpp"
#include "esc/watchdog.hpp"

namespace ecat::esc {

// The 16-bit address space an ESC answers to. Only its registers and its
// configured process RAM are backed by memory (Esc::memory_size()); addresses
// beyond the RAM are "not present" as on silicon (issue 16: a slave costs the
// memory it has, not 64 KiB).
inline constexpr std::size_t kAddressSpace = 0x10000;

class Segment;
namespace engine_detail {
struct CommandTraits;
}

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
  // In place when the access is a fast-path access to a 3-buffer SM
  // (EscConfig::fast_paths) and its bytes are not clipped at the memory's
  // end; otherwise through read()/write().
  std::span<const std::uint8_t> read_buffer(std::uint16_t address, std::span<std::uint8_t> scratch) noexcept override;
  std::span<std::uint8_t> write_buffer_begin(std::uint16_t address, std::span<std::uint8_t> scratch) noexcept override;
  void write_buffer_commit(std::uint16_t address, std::span<const std::uint8_t> bytes) noexcept override;
  // The time of the PDI's accesses: the clock's at each access, or between
  // pin_pdi_time() and unpin_pdi_time() the clock's at the pin. A firmware
  // run (slave::VirtualSlave) pins it: its accesses follow each other within
  // a microsecond or so, and a live run's clock costs a vDSO call a read
  // (~30 ns on the project's VM; bench_cycle BM_Cycle_CspLiveClock: 3 reads
  // a drive and cycle before, 1 with the pin). A simulated clock, which
  // does not move during a run, gives the same times either way.
  void pin_pdi_time() noexcept {
    pdi_time_ = clock_.now();
    pdi_time_pinned_ = true;
  }
  void unpin_pdi_time() noexcept { pdi_time_pinned_ = false; }

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
  // The error counters as silicon has them (Section I §14 Table 51,
  // Section II 0x0300-0x030E; all saturate at 0xFF). What the auto-forwarder
  // of `port` found in a received frame:
  enum class PortError : std::uint8_t {
    InvalidFrame,   // CRC (FCS) error, too long, no SOF: 0x0300+2n
    PhysicalLayer,  // RX_ER (MII) / Manchester violation (EBUS) inside the frame: 0x0300+2n and 0x0301+2n
    Forwarded,      // a frame an earlier ESC already marked as broken: 0x0308+n
  };
  void count_port_error(unsigned port, PortError error) noexcept;
  // A broken frame passed the processing unit (its own or a forwarded
  // error, a datagram structure the unit rejects, a circulating frame it
  // destroys): 0x030C.
  void count_processing_unit_error() noexcept;
  // The PDI found an interface error: 0x030D +1, 0x030E the PDI's error
  // code (Section II 0x030D/0x030E; the code's bits are PDI-specific).
  void count_pdi_error(std::uint8_t code) noexcept;
  // Runs the time-driven parts (watchdogs, SII busy, DC) up to `now`;
  // returns the next time it needs to run, if any.
  std::optional<Nanoseconds> poll(Nanoseconds now) noexcept { return deadline_or_none(advance(now)); }
  // The same with the answer as a time, kNoDeadline when none (the form
  // the slave layer calls: no optional returned through a call).
  Nanoseconds advance(Nanoseconds now) noexcept;

  // Hardware reset (power-on or the 0x0040/0x0041 'R','E','S' sequence):
  // registers to reset values, EEPROM load from the SII image.
  void reset() noexcept;

  // --- Ports (set by esc::Segment) ---
  // Physical link on `port` (0..3): a neighbour is connected. Unconnected
  // ports are closed (looped back) as an ET1100 in Auto loop mode does.
  // Losing a link counts in the lost-link counter 0x0310+port when the
  // port's loop control is Auto or Auto-close, and puts an Auto-close port
  // into "closed wait" (Section I §3.4, Figure 4; Section II 0x0310).
  void set_link(unsigned port, bool link) noexcept;
  // Fault injection (slave::FaultCatalogue): the running process-data
  // watchdog expires at `now` - the next poll(now) shows it as silicon does
  // (0x0440 = 0, 0x0442 + 1, outputs 0x0F00 cleared, AL event bit 6).
  // False when the watchdog is not running.
  bool expire_process_data_watchdog(Nanoseconds now) noexcept {
    if (!watchdogs_.expire_process_data(now)) return false;
    refresh_timers();
    return true;
  }
  // Fault injection (esc/esc_faults.cpp): byte `at` of the EEPROM set to
  // `value` (a copy of its own for a shared image; nothing written back to
  // a file), then the EEPROM reloaded as the 0x0502 reload command does -
  // e.g. a bad SII checksum (word 7) shows as 0x0502 bits 11/12 and 0x0110
  // bit 0 = 0. Returns the byte it replaced; nullopt (nothing changed) when
  // the image has no byte `at`.
  std::optional<std::uint8_t> patch_eeprom_and_reload(std::size_t at, std::uint8_t value);
  // Fault injection (tests: an ESC whose silicon shows other register
  // values, e.g. a reset value the datasheet does not give): register bytes
  // 0x0000-0x0FFF written as they are, no side effects, no access rules.
  // Only registers the ESC keeps in its memory change what a read returns;
  // SMs, FMMUs and the DC block (0x0900-0x09FF) keep their own state.
  static constexpr std::size_t kRegisterEnd = 0x1000;
  void poke_registers(std::uint16_t address, std::span<const std::uint8_t> bytes) noexcept;
  // The SII interface stuck busy from its next command on (SiiInterface::set_stuck).
  void set_sii_stuck(bool stuck, Nanoseconds now) noexcept;
  bool link(unsigned port) const noexcept { return port < kMaxPorts && link_[port]; }
  // Whether `port` exists on this ESC (0x0007 bits 2n+1:2n not 00).
  bool port_present(unsigned port) const noexcept { return port < kMaxPorts && present_[port]; }
  // A valid frame arrived from the wire at `port` while it is closed: an
  // Auto-close port in "closed wait" opens (Section I §3.4, Figure 4).
  // The frame itself is not taken in (a closed port does not receive).
  void frame_at_closed_port(unsigned port) noexcept;
  // Whether a frame leaving the processing unit toward `port` goes out
  // (open) or is looped back (closed), per link and DL control loop bits
  // (cached; recomputed when the link or DL control changes).
  bool port_open(unsigned port) const noexcept { return port < kMaxPorts && port_open_[port]; }

  // --- Accessors for tests and the slave layer ---
  // Registers 0x0000-0x0FFF, then the process RAM: memory_size() bytes
  // (0x1000 + EscConfig::process_ram_size); nothing beyond is stored.
  const std::uint8_t* memory() const noexcept { return mem_.get(); }
  std::size_t memory_size() const noexcept { return ram_end(); }
  // The bytes of its mapping: memory_size() and room for the largest colour
  // offset, the same for every colour (esc/esc_memory.cpp).
  std::size_t memory_mapped() const noexcept { return mem_.get_deleter().size; }
  // Raw little-endian register value without side effects (the DC block is
  // read through DcUnit as a PDI read); bytes beyond the RAM read as 0.
  std::uint16_t register_u16(std::uint16_t address) const noexcept;
  const EscConfig& config() const noexcept { return config_; }
  DcUnit& dc() noexcept {
    touch();  // the caller may change the DC unit's events or times
    return dc_;
  }
  const DcUnit& dc() const noexcept { return dc_; }
  // Whether anything accessed this ESC from outside a frame since the last
  // take_in_accesses(). The segment's dirty set says the same until the
  // segment reads the ESC again at its next frame; this tells a user that
  // takes the ESC's state in after its own firmware ran (slave::Chain)
  // whether any access came after that (issue 30: the one-drive cycle
  // noted its slave twice, for its own firmware's accesses).
  bool accessed() const noexcept { return hook_.accessed; }
  void take_in_accesses() noexcept { hook_.accessed = false; }
  // SM n; one this ESC does not have (n >= the count in 0x0005) is a
  // disabled SM whose registers are what those registers read (0, status
  // 0x30).
  const SyncManager& sync_manager(unsigned n) const noexcept;
  // True when (AL event request & AL event mask) != 0: the IRQ pin to the µC
  // (Section II 0x0204/0x0220). Cheap: a few loads. The mask is 0 after
  // reset, so firmware that relies on irq() must write 0x0204 first.
  bool irq() const noexcept { return (al_event() & load_le<std::uint32_t>(mem_.get() + reg::kAlEventMask)) != 0; }
  // True when any AL event request bit is set, whatever the mask: something
  // the application must look at (AL control written, SM activation changed,
  // an SM buffer event with SM control bit 5, watchdog expired, DC SYNC/latch).
  // Lets a host decide which slaves' firmware to run after a frame without
  // depending on the mask the firmware chose.
  bool pdi_attention() const noexcept { return al_event() != 0; }
  // The AL event request 0x0220 as a PDI read would see it (DC bits ORed
  // in), without the read's side effects: a PDI host's interrupt line.
  std::uint32_t al_event_request() const noexcept { return al_event(); }
  // The earliest time the ESC's own timers (watchdogs, SII busy) need to
  // run; Nanoseconds::max() when none is armed. DC SYNC is in dc().poll().
  Nanoseconds next_timer() const noexcept { return next_timer_; }
  // A time before which poll() does nothing but note the time: next_timer()
  // (kept exact at every access) and the DC unit's DcUnit::wake_bound().
  // Nanoseconds::max(): nothing armed. Read after any access, it already
  // holds what that access armed (slave::Chain polls by it).
  Nanoseconds wake_bound() const noexcept { return std::min(next_timer_, dc_.wake_bound()); }
  // Time of the latest access: frame, PDI access or poll.
  Nanoseconds last_time() const noexcept {
    const_cast<Esc*>(this)->sync_pass();
    return now_;
  }

 private:
  // Register space 0x0000-0x0FFF from either side (esc/register_access.cpp).
  // Return true if the access counts for the WKC.
  bool reg_read(std::uint16_t address, std::span<std::uint8_t> out, Side side) noexcept;
  bool reg_write(std::uint16_t address, std::span<const std::uint8_t> in, Side side) noexcept;
  // Byte by byte through the handlers (every byte when !fast_paths).
  bool reg_read_checked(std::uint16_t address, std::span<std::uint8_t> out, Side side) noexcept;
  bool reg_write_checked(std::uint16_t address, std::span<const std::uint8_t> in, Side side, bool checked) noexcept;
  std::uint8_t reg_read_byte(std::uint16_t address, Side side) noexcept;
  bool reg_write_byte(std::uint16_t address, std::uint8_t value, Side side) noexcept;
  void after_register_write(std::uint16_t address, std::uint8_t old_value, Side side) noexcept;

  // Whole address space through the sync managers (esc/memory_access.cpp).
  // Return true if at least one byte was accessible (WKC rule, ETG.1000.4 §5.4.3).
  bool mem_read(std::uint16_t address, std::span<std::uint8_t> out, Side side) noexcept;
  bool mem_write(std::uint16_t address, std::span<const std::uint8_t> in, Side side) noexcept;
  // Raw copy without side effects (bit-wise FMMU writes start from it).
  void peek(std::uint32_t address, std::span<std::uint8_t> out) const noexcept;

  // Frames a segment let pass by (esc/pass_hook.hpp): the times they left
  // are taken in before anything looks at this ESC (sync_pass), and any
  // access from outside a frame also marks it for the segment to read again
  // (touch), since it may change what the segment knows of it.
  void sync_pass() noexcept {
    if (hook_.line != nullptr && hook_.synced != hook_.line->frame) apply_pass();
  }
  void apply_pass() noexcept;
  void apply_route_passes(const LinePass& p) noexcept;
  // A frame that maps a run of ESCs (an LRW of a long line) finds each one
  // cold: its lines were last read a cycle ago, a thousand ESCs back. The
  // segment asks for them a few ESCs ahead of the pass (Segment::carry_line,
  // esc/logical_access.hpp): first the object's lines the pass reads, then
  // those its pointers lead to. A prefetch never faults and changes nothing
  // but the caches (issue 30 item 1, docs/performance-log.md "Session 22").
  inline void prefetch_pass_object() const noexcept;
  inline void prefetch_pass_targets() const noexcept;
  void touch() noexcept {
    sync_pass();
    hook_.accessed = true;
    if (hook_.dirty_word != nullptr) *hook_.dirty_word |= hook_.dirty_bit;
  }

  // Datagram engine (inline in esc/datagram_engine.hpp, which esc::Segment
  // includes: a frame's pass through an ESC is compiled into its loop).
  friend class Segment;
  bool process_datagrams(DatagramView first, std::size_t count, Nanoseconds now) noexcept;
  void process_datagram(DatagramView d) noexcept;
  void process_addressed(DatagramView d, const engine_detail::CommandTraits& traits, bool addressed,
                         bool broadcast) noexcept;
  void process_merged(DatagramView d, bool read_write, bool broadcast) noexcept;
  // The data of an ECAT read (FPRD/APRD/xRMW): register bytes inline, else mem_read.
  bool ecat_read(std::uint16_t address, Bytes out) noexcept;
  bool system_time_rmw(DatagramView d, bool addressed) noexcept;
  // Logical addressing (esc/logical_access.hpp / .cpp).
  std::uint16_t process_logical(DatagramView d) noexcept;
  std::uint16_t process_logical_routes(DatagramView d) noexcept;
  std::uint16_t process_logical_bits(DatagramView d) noexcept;
  bool addressed_configured(std::uint16_t adp) const noexcept;
  // Register write protection (0x0021/0x0031) active and not released in
  // this frame: ECAT register writes take the checked path.
  bool write_protection_active() const noexcept;

  // Events (esc/esc.cpp). The request registers live in memory; the DC unit's
  // bits are ORed in on every read.
  std::uint32_t al_event() const noexcept {
    return load_le<std::uint32_t>(mem_.get() + reg::kAlEventRequest) | dc_.al_event_request();
  }
  std::uint16_t ecat_event() const noexcept {
    return static_cast<std::uint16_t>(load_le<std::uint16_t>(mem_.get() + reg::kEcatEventRequest) |
                                      dc_.ecat_event_request());
  }
  void set_al_event(std::uint32_t b) noexcept {
    std::uint8_t* p = mem_.get() + reg::kAlEventRequest;
    store_le(p, load_le<std::uint32_t>(p) | b);
  }
  void clear_al_event(std::uint32_t b) noexcept {
    std::uint8_t* p = mem_.get() + reg::kAlEventRequest;
    store_le(p, load_le<std::uint32_t>(p) & ~b);
  }
  void set_ecat_event(std::uint16_t b) noexcept {
    std::uint8_t* p = mem_.get() + reg::kEcatEventRequest;
    store_le(p, static_cast<std::uint16_t>(load_le<std::uint16_t>(p) | b));
  }
  void clear_ecat_event(std::uint16_t b) noexcept {
    std::uint8_t* p = mem_.get() + reg::kEcatEventRequest;
    store_le(p, static_cast<std::uint16_t>(load_le<std::uint16_t>(p) & ~b));
  }
  // SyncManager interrupts: AL event bit 8+n, ECAT event bit 4+n (n < 8),
  // and the process-data watchdog restart; inline, as it follows every SM
  // access of a frame.
  void apply(unsigned sm, const SmSignals& sig) noexcept;
  void restart_process_data_watchdog() noexcept;
  // The IRQ field this ESC ORs into a datagram: (0x0210 | DC) & 0x0200.
  // 0 while the mask is (most masters never set it), without a look at the
  // event registers or the DC unit.
  std::uint16_t irq_field() const noexcept {
    if (ecat_event_mask_ == 0) return 0;
    return static_cast<std::uint16_t>(ecat_event() & ecat_event_mask_);
  }
  // 0x0200 changed (ECAT write, reset, poke_registers).
  void ecat_event_mask_written() noexcept { ecat_event_mask_ = load_le<std::uint16_t>(mem_.get() + reg::kEcatEventMask); }
  void update_dl_status() noexcept;
  // DL control 0x0101 written: Auto-close ports leave "closed wait".
  void loop_control_written() noexcept;
  std::uint32_t loop_control(unsigned port) const noexcept;
  // Caches (see "Speed" above).
  void update_ports() noexcept;
  void update_sm_guards() noexcept;
  void update_fmmus() noexcept;
  // next_timer_ = the earliest of the watchdogs' and the SII's deadlines.
  // Every change of the SII's deadline is followed by refresh_timers, which
  // keeps it in sii_timer_; a watchdog trigger changes only the watchdogs'
  // and takes the SII's from there (refresh_watchdog_timer), without the
  // SII's lines.
  void refresh_timers() noexcept {
    sii_timer_ = sii_.next_deadline().value_or(Nanoseconds::max());
    refresh_watchdog_timer();
  }
  void refresh_watchdog_timer() noexcept { next_timer_ = std::min(watchdogs_.earliest(), sii_timer_); }
  // The watchdog registers 0x0400, 0x0410 or 0x0420 changed.
  void watchdog_times_written() noexcept;
  void load_eeprom(bool power_on) noexcept;
  // Runs the watchdogs and the SII busy time when one is due (now >= next_timer_).
  void run_timers(Nanoseconds now) noexcept {
    if (now >= next_timer_) run_due_timers(now);
  }
  void run_due_timers(Nanoseconds now) noexcept;
  void pdi_watchdog_trigger(Nanoseconds t) noexcept;
  // The time of a PDI access (pin_pdi_time).
  Nanoseconds pdi_now() const noexcept { return pdi_time_pinned_ ? pdi_time_ : clock_.now(); }
  // PDI fast paths (esc.cpp): true when the access was carried out.
  bool pdi_read_fast(std::uint16_t address, std::span<std::uint8_t> out) noexcept;
  [[gnu::noinline]] bool pdi_read_dc(std::uint32_t address, std::uint32_t end, std::span<std::uint8_t> out) noexcept;
  void pdi_sm_registers_read(std::uint32_t address, std::uint32_t end) noexcept;
  // What a PDI read of byte `off` of SM n's registers acknowledges (Section
  // II 0x0805, 0x0806): an activate byte the SM activation event (0x0220 bit
  // 4); a status byte SM n's event (bit 8+n), which mirrors status bits 0/1
  // that on silicon only an access to the buffer clears (Section II 0x0220,
  // 0x0805; EscConfig::sm_status_read_clears_event). SMs the ESC lacks: none.
  void pdi_sm_read_acknowledge(unsigned n, unsigned off) noexcept {
    if (n >= config_.sync_manager_count) return;
    if (off == reg::sm::kActivate) clear_al_event(bits::kAlEventSmActivation);
    if (off == reg::sm::kStatus && config_.sm_status_read_clears_event) {
      clear_al_event(1u << (bits::kAlEventSmShift + n));
    }
  }
  bool pdi_write_fast(std::uint16_t address, std::span<const std::uint8_t> in) noexcept;
  int pdi_sm_for(std::uint32_t address, std::uint32_t end) const noexcept;
  // The 3-buffer SM a whole-buffer PDI access in place goes to (fast path,
  // buffered, PDI reads when !write / writes when write), or -1. The last
  // answer per direction is kept until an SM register changes (update_sm_guards,
  // reset): the process-data cycle asks the same three questions every time.
  int pdi_in_place_sm(std::uint16_t address, std::size_t n, bool write) noexcept {
    const PdiBufferHint& hint = pdi_buffer_hints_[write ? 1 : 0];
    if (hint.sm >= 0 && hint.address == address && hint.size == n) return hint.sm;
    return pdi_find_in_place_sm(address, n, write);
  }
  int pdi_find_in_place_sm(std::uint16_t address, std::size_t n, bool write) noexcept;
  void sii_action(SiiInterface::Action a) noexcept;
  std::uint32_t dl_control() const noexcept;
  std::uint32_t ram_end() const noexcept { return reg::kProcessRam + config_.process_ram_size; }

  EscConfig config_;
  // The SM, FMMU and route tables, sized to the units this ESC has
  // (config_.sync_manager_count / fmmu_count = 0x0005 / 0x0004), not to
  // the 16 the register block has room for (issue 16 item 5: memory per
  // slave). One allocation (allocate_units) holds the routes, the SMs and
  // the FMMUs; the registers of a unit the ESC lacks read 0 and are never
  // written (register_write_mask), so no state is kept for it.
  std::unique_ptr<std::byte[]> units_;
  Fmmu* fmmus_ = nullptr;       // [fmmu_count]
  void allocate_units();
  std::uint32_t sm_enabled_ = 0;    // bit n: SM n enabled (guards its area)
  // Whether [first, end) holds the byte of a watchdog-trigger-only SM.
  bool touches_watchdog_only_sm(std::uint32_t first, std::uint32_t end) const noexcept;
  std::uint32_t fmmu_active_ = 0;   // bit n: FMMU n active
  // The active FMMUs decoded for the routed LRD/LWR/LRW path
  // (esc/logical_access.cpp): logical byte range, physical start and where
  // the physical range goes - SM n (>= 0), plain RAM, or mem_read/mem_write;
  // a write over plain RAM that holds the byte of a 1-byte SM (watchdog
  // trigger only, Section II 0x0802) is plain RAM that restarts the
  // process-data watchdog when the written bytes reach that byte.
  static constexpr std::int8_t kRouteGeneral = -1;
  static constexpr std::int8_t kRouteRam = -2;
  static constexpr std::int8_t kRouteRamWatchdog = -3;
  struct FmmuRoute {
    std::uint64_t first = 0;  // logical bytes [first, end)
    std::uint64_t end = 0;
    std::uint32_t physical = 0;
    std::int8_t target = kRouteGeneral;
    // SM target whose whole buffer this FMMU maps, ready for
    // SyncManager::ecat_read_whole/ecat_write_whole; with the event bits
    // that access raises and clears and whether it restarts the watchdog
    // (decoded from the SM registers, which re-route on every change).
    bool whole = false;
    bool watchdog = false;
    std::uint16_t ecat_clear = 0;
    std::uint32_t al_raise = 0;
    // kRouteRamWatchdog: the physical bytes [watchdog_first, watchdog_end)
    // of the one watchdog-only SM the route covers, which a write must reach
    // to restart the watchdog; watchdog_end 0 when it covers several (then
    // restart_watchdog_over looks at the SMs).
    std::uint32_t watchdog_first = 0;
    std::uint32_t watchdog_end = 0;
  };
  // The route of one FMMU direction with its whole-buffer decoding (logical_access.cpp).
  FmmuRoute whole_route(FmmuRoute r, std::uint32_t length, bool ecat_write) const noexcept;
  void whole_events(const FmmuRoute& r) noexcept;
  void restart_watchdog_over(std::uint64_t address, std::size_t size) noexcept;
  void restart_watchdog_over(const FmmuRoute& r, std::uint64_t address, std::size_t size) noexcept;
  // The one watchdog-only SM over physical bytes [first, end): its bytes, or {0, 0} for none or several.
  std::pair<std::uint32_t, std::uint32_t> watchdog_only_sm_over(std::uint32_t first, std::uint32_t end) const noexcept;
  SiiInterface sii_;
  DcUnit dc_;  // its per-frame members last, next to the ones below
  // What every frame reads at every ESC, together in the object's last
  // lines (only the cyclic datagrams' members below come after them), right
  // after the DC unit's frame-arrival state (issue 8: a 1000-ESC line
  // touches a few lines per ESC, not one per member).
  // memory_size() bytes, mapped once (esc/esc_memory.cpp): pages the ESC
  // never touches - most of a large process RAM - are not resident.
  struct MemoryUnmap {
    std::size_t size;  // of the whole mapping; no initializer: default-constructible inside the incomplete Esc
    void operator()(std::uint8_t* p) const noexcept;
  };
  // What esc::Segment's skip index reads of an ESC accessed since the last
  // frame (Segment::note_entered), first: with the DC unit's last members
  // (receive_latch_armed_) one line, where the ESC was read over three or
  // four (issue 30 item 1, docs/performance-log.md "Session 15").
  Nanoseconds next_timer_ = Nanoseconds::max();
  Nanoseconds sii_timer_ = Nanoseconds::max();  // the SII's deadline at the last refresh_timers
  std::uint32_t fmmu_epoch_ = 0;  // +1 at every update_fmmus (esc::Segment re-reads the spans)
  // +1 whenever something esc::Segment's skip index keeps of this ESC's
  // addressing, ports and reset may have changed: a write to the station
  // address 0x0010, the alias 0x0012, DL control 0x0100-0x0103 (loop bits,
  // alias enable) or the ECAT event mask 0x0200; the ports (update_ports:
  // link, loop, reset); an ESC reset requested (0x0040/0x0041); an EEPROM
  // load; poke_registers. The segment reads those registers again only
  // when it moved.
  std::uint32_t address_epoch_ = 0;
  std::unique_ptr<std::uint8_t[], MemoryUnmap> mem_;
  static std::unique_ptr<std::uint8_t[], MemoryUnmap> map_memory(std::size_t size, unsigned colour);
  Nanoseconds now_{0};
  // Logical bytes [logical_first_, logical_end_) span every active FMMU:
  // a logical datagram outside it passes this ESC untouched.
  std::uint64_t logical_first_ = 0;
  std::uint64_t logical_end_ = 0;
  std::array<bool, kMaxPorts> link_{};
  std::array<bool, kMaxPorts> port_open_{};
  // What a line of ESCs (esc::Segment's line path) does after the processing
  // unit, from port_open_ and link_ (update_ports): on to port 1's
  // neighbour, back toward port 0 (ports 3, 1, 2 closed), or lost (an open
  // port 2/3, or port 1 open with no link).
  enum class LineRoute : std::uint8_t { Down, Back, Lost };
  LineRoute line_route_ = LineRoute::Back;
  std::array<bool, kMaxPorts> present_{};      // the port exists (0x0007)
  std::array<bool, kMaxPorts> closed_wait_{};  // Auto-close port closed after a link loss
  bool memory_fresh_ = true;  // still all zero as mapped: the power-on reset need not clear it
  // The ECAT event mask 0x0200 as stored (ecat_event_mask_written): every
  // datagram at every ESC asks for it (irq_field).
  std::uint16_t ecat_event_mask_ = 0;
  // pdi_in_place_sm's last answers: [0] reads, [1] writes; sm -1 = none kept.
  struct PdiBufferHint {
    std::uint32_t address = 0;
    std::uint32_t size = 0;
    int sm = -1;
  };
  std::array<PdiBufferHint, 2> pdi_buffer_hints_{};
  bool fmmus_routed_ = true;  // whole bytes, no logical byte both read and written
  // Per-frame state: write-protection release (0x0020/0x0030 written this frame).
  bool register_write_enabled_ = false;
  bool esc_write_enabled_ = false;
  bool reset_requested_ = false;
  // ESC reset sequence progress for 0x0040 (ECAT) and 0x0041 (PDI).
  std::array<std::uint8_t, 2> reset_step_{};
  // AL control written by ECAT and not yet read by the PDI (Section II 0x0120).
  bool al_control_pending_ = false;
  PassHook hook_;  // set by esc::Segment's line
  // What a cyclic frame's LRW and DC datagrams and the firmware's accesses
  // read of the ESC besides the members above and its memory: the clock,
  // the SM and route tables, the watchdogs. Last, right after the members
  // every frame reads, where they sat in two lines of their own; frames that
  // read none of them (a BRD, an FPRD elsewhere) touch no more lines than
  // before (issue 30 item 1: with the DC unit's order, a drive's ESC object
  // in 11 lines a cycle instead of 14; scripts/lines-per-drive).
  const Clock& clock_;
  SyncManager* sms_ = nullptr;  // [sync_manager_count]
  std::uint32_t sm_watchdog_only_ = 0;  // bit n: SM n of length 1 or over registers, watchdog trigger only
  bool pdi_time_pinned_ = false;        // pin_pdi_time (in the hole before routes_)
  FmmuRoute* routes_ = nullptr;        // [fmmu_count] read routes, route_reads_ of them in use
  FmmuRoute* write_routes_ = nullptr;  // [fmmu_count] write routes, route_writes_ in use
  unsigned route_reads_ = 0;
  unsigned route_writes_ = 0;
  Watchdogs watchdogs_;
  Nanoseconds pdi_time_{0};  // pin_pdi_time; on the line of the watchdogs, which every PDI access reads
};

// SyncManager interrupts (Section II 0x0210/0x0220).
// Each request register is read and written once (clear, then raise).
inline void Esc::apply(unsigned n, const SmSignals& sig) noexcept {
  std::uint8_t* m = mem_.get();
  if (sig.clear_al || sig.raise_al) {
    const std::uint32_t al = 1u << (bits::kAlEventSmShift + n);
    std::uint32_t v = load_le<std::uint32_t>(m + reg::kAlEventRequest);
    if (sig.clear_al) v &= ~al;
    if (sig.raise_al) v |= al;
    store_le(m + reg::kAlEventRequest, v);
  }
  if ((sig.clear_ecat || sig.raise_ecat) && n < bits::kEcatEventSmCount) {
    const auto ecat = static_cast<std::uint16_t>(1u << (bits::kEcatEventSmShift + n));
    auto v = load_le<std::uint16_t>(m + reg::kEcatEventRequest);
    if (sig.clear_ecat) v = static_cast<std::uint16_t>(v & ~ecat);
    if (sig.raise_ecat) v = static_cast<std::uint16_t>(v | ecat);
    store_le(m + reg::kEcatEventRequest, v);
  }
  if (sig.watchdog_trigger) restart_process_data_watchdog();
}

// Whether bytes [first, end) reach an SM that only triggers the watchdog
// (sm_watchdog_only_).
inline bool Esc::touches_watchdog_only_sm(std::uint32_t first, std::uint32_t end) const noexcept {
  for (std::uint32_t left = sm_watchdog_only_; left != 0; left &= left - 1) {
    const SyncManager& sm = sms_[static_cast<unsigned>(std::countr_zero(left))];
    const std::uint32_t at = sm.start();
    const std::uint32_t sm_end = at + std::max<std::uint32_t>(sm.length(), 1);
    if (at < end && first < sm_end) return true;
  }
  return false;
}

inline void Esc::restart_process_data_watchdog() noexcept {
  watchdogs_.trigger_process_data(now_);
  if (!watchdogs_.pd_status_shown()) [[unlikely]] {
    mem_[reg::kWatchdogStatusProcessData] = bits::kWatchdogPdActive;
    watchdogs_.set_pd_status_shown();
  }
  refresh_watchdog_timer();
}

}  // namespace ecat::esc
