// Esc construction, reset/EEPROM load, PDI entry points, timers, ports and
// event registers (Section I §3, §10, §11; Section II 0x0000-0x0220).
#include "esc/esc.hpp"

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstring>
#include <memory>
#include <type_traits>

#include "esc/register_masks.hpp"
#include "esc/registers.hpp"

namespace ecat::esc {

namespace {
constexpr std::uint16_t kKiB = 1024;
constexpr std::size_t kSiiWordPdiControl = 0;
constexpr std::size_t kSiiWordPdiConfig = 1;
constexpr std::size_t kSiiWordSyncPulse = 2;
constexpr std::size_t kSiiWordExtPdiConfig = 3;
constexpr std::size_t kSiiWordAlias = 4;
constexpr std::size_t kSiiWordChecksum = 7;

std::uint16_t sii_word(const EepromImage& sii, std::size_t w) {
  return load_le<std::uint16_t>(sii.data() + 2 * w);
}
}  // namespace

Esc::Esc(EscConfig config, const Clock& clock)
    : config_(std::move(config)), clock_(clock) {
  config_.fmmu_count = std::min(config_.fmmu_count, kMaxFmmus);
  config_.sync_manager_count = std::min(config_.sync_manager_count, kMaxSyncManagers);
  config_.port_count = std::min(config_.port_count, kMaxPorts);
  for (unsigned p = 0; p < kMaxPorts; ++p) {
    present_[p] = config_.port_descriptor != 0 ? port_type_in(config_.port_descriptor, p) != PortType::NotImplemented
                                               : p < config_.port_count;
  }
  config_.process_ram_size = std::min(config_.process_ram_size, kMaxProcessRam);
  // Registers and the configured RAM only (issue 16): every access beyond
  // ram_end() is clipped before it reaches memory (mem_read/mem_write, the
  // SMs' memory_end, the FMMU routes, peek, register_u16).
  mem_ = map_memory(memory_size(), config_.memory_colour);
  allocate_units();
  for (unsigned n = 0; n < config_.sync_manager_count; ++n) {
    sms_[n].bind(mem_.get() + reg::sync_manager(n), mem_.get(), ram_end());
  }
  sii_.bind(mem_.get() + reg::kEepromConfiguration, config_);
  now_ = clock_.now();
  reset();
}

Esc::~Esc() = default;

namespace {
// `n` value-initialised T at `at` (storage of units_), `at` moved past them.
template <typename T>
T* construct_units(std::byte*& at, std::size_t n) {
  static_assert(std::is_trivially_destructible_v<T>, "units_ is freed without destroying its objects");
  static_assert(alignof(T) <= alignof(std::max_align_t) && sizeof(T) % alignof(std::uint64_t) == 0,
                "every table starts aligned for the next");
  T* first = reinterpret_cast<T*>(at);
  std::uninitialized_value_construct_n(first, n);
  at += n * sizeof(T);
  return first;
}
}  // namespace

// Routes first (the frame path reads them), then SMs, then FMMUs.
void Esc::allocate_units() {
  const std::size_t fmmus = config_.fmmu_count;
  const std::size_t sms = config_.sync_manager_count;
  units_ = std::make_unique_for_overwrite<std::byte[]>(2 * fmmus * sizeof(FmmuRoute) + sms * sizeof(SyncManager) +
                                                        fmmus * sizeof(Fmmu));
  std::byte* at = units_.get();
  routes_ = construct_units<FmmuRoute>(at, fmmus);
  write_routes_ = construct_units<FmmuRoute>(at, fmmus);
  sms_ = construct_units<SyncManager>(at, sms);
  fmmus_ = construct_units<Fmmu>(at, fmmus);
}

const SyncManager& Esc::sync_manager(unsigned n) const noexcept {
  if (n < config_.sync_manager_count) return sms_[n];
  // Registers as those of a missing SM read (see reset()); only read
  // through the const reference once bound.
  static std::array<std::uint8_t, reg::kSyncManagerStride> absent_registers{};
  static const SyncManager absent = [] {
    SyncManager sm;
    sm.bind(absent_registers.data(), nullptr, 0);
    return sm;
  }();
  return absent;
}

std::uint32_t Esc::dl_control() const noexcept { return load_le<std::uint32_t>(mem_.get() + reg::kDlControl); }

std::uint16_t Esc::register_u16(std::uint16_t address) const noexcept {
  const_cast<Esc*>(this)->sync_pass();  // the DC block is read at the latest access time
  if (address >= reg::kDcBase && address < reg::kDcEnd) {
    std::uint8_t b[2]{};
    const_cast<DcUnit&>(dc_).read(static_cast<std::uint16_t>(address - reg::kDcBase), b, now_, Side::Pdi);
    return load_le<std::uint16_t>(b);
  }
  if (address + sizeof(std::uint16_t) <= ram_end()) return load_le<std::uint16_t>(mem_.get() + address);
  std::uint8_t b[2]{};
  peek(address, b);  // at or past the RAM's end: the missing bytes read as 0
  return load_le<std::uint16_t>(b);
}

// Power-on / ESC reset: every register to its reset value (Section II), RAM
// cleared, then the EEPROM load of the configuration area.
void Esc::reset() noexcept {
  touch();
  if (!memory_fresh_) std::memset(mem_.get(), 0, memory_size());
  memory_fresh_ = false;
  std::uint8_t* m = mem_.get();
  m[reg::kType] = config_.type;
  m[reg::kRevision] = config_.revision;
  store_le(m + reg::kBuild, config_.build);
  m[reg::kFmmusSupported] = config_.fmmu_count;
  m[reg::kSyncManagersSupported] = config_.sync_manager_count;
  m[reg::kRamSize] = static_cast<std::uint8_t>(config_.process_ram_size / kKiB);
  std::uint8_t ports = config_.port_descriptor;
  if (ports == 0) {
    for (unsigned p = 0; p < config_.port_count; ++p) {
      ports = static_cast<std::uint8_t>(ports | (static_cast<unsigned>(config_.port_type) << (2 * p)));
    }
  }
  m[reg::kPortDescriptor] = ports;
  std::uint16_t features = 0;
  if (config_.dc) features |= bits::kFeatureDc;
  if (config_.dc && config_.dc_64bit) features |= bits::kFeatureDc64;
  if (config_.dc && config_.enhanced_dc_sync) features |= bits::kFeatureEnhancedDcSync;
  if (!config_.lrw) features |= bits::kFeatureNoLrw;
  if (!config_.read_write_commands) features |= bits::kFeatureNoReadWrite;
  store_le(m + reg::kFeatures, features);
  store_le(m + reg::kDlControl, bits::kDlControlReset);
  store_le(m + reg::kAlControl, bits::kAlControlReset);
  store_le(m + reg::kAlStatus, bits::kAlStatusReset);
  store_le(m + reg::kWatchdogDivider, kWatchdogDividerReset);
  store_le(m + reg::kWatchdogTimePdi, kWatchdogTimeReset);
  store_le(m + reg::kWatchdogTimeProcessData, kWatchdogTimeReset);
  m[reg::kWatchdogStatusProcessData] = bits::kWatchdogPdActive;
  for (unsigned n = 0; n < config_.sync_manager_count; ++n) sms_[n].reset_state();
  // An SM the ESC lacks keeps no state, and its registers are never
  // written; its status byte reads as that of an SM with control 0 after
  // reset (3-buffer mode, no buffer written: 0x30), as it did when every
  // ESC reset 16 SMs.
  for (unsigned n = config_.sync_manager_count; n < kMaxSyncManagers; ++n) {
    m[reg::sync_manager(n) + reg::sm::kStatus] =
        static_cast<std::uint8_t>(sm_bits::kNoBufferWritten << sm_bits::kStatusBufferShift);
  }
  std::fill_n(fmmus_, config_.fmmu_count, Fmmu{});
  sm_enabled_ = 0;
  sm_watchdog_only_ = 0;
  pdi_buffer_hints_ = {};
  update_fmmus();
  watchdogs_.reset();
  ecat_event_mask_ = 0;  // 0x0200 cleared above
  register_write_enabled_ = false;
  esc_write_enabled_ = false;
  reset_step_ = {};
  reset_requested_ = false;
  al_control_pending_ = false;
  closed_wait_ = {};
  load_eeprom(true);
  refresh_timers();
  update_ports();
  update_dl_status();
}

// EEPROM load of the configuration area (Section I §11.1; sii-eeprom.md §1-2).
// The alias (word 4) is taken only at power-on, and a reload keeps 0x0141
// bits 1 and 4-7.
void Esc::load_eeprom(bool power_on) noexcept {
  const auto& sii = config_.sii;
  bool ok = sii.size() >= 2 * (kSiiWordChecksum + 1);
  if (ok) {
    const std::uint16_t stored = sii_word(sii, kSiiWordChecksum);
    ok = stored == kSiiChecksumDisabled ||
         (stored & 0xFF) == sii_crc(std::span(sii.data(), kSiiConfigAreaBytes));
  }
  std::uint8_t* m = mem_.get();
  if (power_on) {
    sii_.reset(ok);
  } else {
    sii_.set_checksum_ok(ok);
  }
  if (!ok) {
    if (power_on) dc_.reset(0);
    return;
  }
  const std::uint16_t w0 = sii_word(sii, kSiiWordPdiControl);
  m[reg::kPdiControl] = static_cast<std::uint8_t>(w0);
  const auto esc_config = static_cast<std::uint8_t>(w0 >> 8);
  m[reg::kEscConfiguration] =
      power_on ? esc_config
               : static_cast<std::uint8_t>((m[reg::kEscConfiguration] & bits::kEscConfigKeptOnReload) |
                                           (esc_config & ~bits::kEscConfigKeptOnReload));
  store_le(m + reg::kPdiConfiguration, sii_word(sii, kSiiWordPdiConfig));
  store_le(m + reg::kExtendedPdiConfiguration, sii_word(sii, kSiiWordExtPdiConfig));
  if (power_on) {
    store_le(m + reg::kConfiguredStationAlias, sii_word(sii, kSiiWordAlias));
    ++address_epoch_;
    dc_.reset(sii_word(sii, kSiiWordSyncPulse));
  }
}

// --- PDI side ---------------------------------------------------------------------

// Speed (issue 8): with EscConfig::fast_paths, the accesses a firmware
// makes every cycle skip the general memory walk - the AL event request
// 0x0220-0x0223 (read without side effect from the PDI, so the value with the
// DC bits ORed in is the whole answer) and an access that lies inside one
// enabled SM's area (the SM rules directly, as mem_read would do in its first
// and only step) - and no PDI access recomputes the DL status: every input of
// 0x0110 (link, loop, EEPROM loaded, enhanced link, PDI watchdog) already
// updates it where it changes (set_link, DL control and EEPROM writes, SII
// reload, reset, watchdog expiry), and the one bit a PDI access sets is set
// in pdi_watchdog_trigger. Without fast_paths every access takes the general
// path and recomputes 0x0110, and tests/esc/esc_pdi_fast_path_test.cpp
// compares the two.
void Esc::read(std::uint16_t address, std::span<std::uint8_t> out) noexcept {
  touch();
  const Nanoseconds t = pdi_now();
  run_timers(t);
  now_ = t;
  if (!config_.fast_paths || !pdi_read_fast(address, out)) {
    // Bytes that are not there (past the RAM or the address space) or that a
    // sync manager refuses read as 0.
    std::fill(out.begin(), out.end(), std::uint8_t{0});
    const std::size_t n = std::min<std::size_t>(out.size(), kAddressSpace - address);
    mem_read(address, out.first(n), Side::Pdi);
  }
  pdi_watchdog_trigger(t);
  if (!config_.fast_paths) update_dl_status();
}

void Esc::write(std::uint16_t address, std::span<const std::uint8_t> in) noexcept {
  touch();
  const Nanoseconds t = pdi_now();
  run_timers(t);
  now_ = t;
  if (!config_.fast_paths || !pdi_write_fast(address, in)) {
    const std::size_t n = std::min<std::size_t>(in.size(), kAddressSpace - address);
    mem_write(address, in.first(n), Side::Pdi);
  }
  pdi_watchdog_trigger(t);
  if (reset_requested_) {
    dc_.note_time(t);  // the DC time loop's correction ends at the reset (DcUnit::reset)
    reset();  // recomputes 0x0110 itself
  }
  if (!config_.fast_paths) update_dl_status();
}

// The lowest-numbered enabled SM whose area holds [address, end), or -1 when
// the access starts outside every SM, crosses an area's end or the RAM's:
// then mem_read/mem_write split it (find_guard takes the lowest SM too).
int Esc::pdi_sm_for(std::uint32_t address, std::uint32_t end) const noexcept {
  if (address < reg::kProcessRam || end > ram_end()) return -1;
  for (std::uint32_t left = sm_enabled_; left != 0; left &= left - 1) {
    const auto n = static_cast<unsigned>(std::countr_zero(left));
    const SyncManager& sm = sms_[n];
    if (address >= sm.start() && address < sm.end()) return end <= sm.end() ? static_cast<int>(n) : -1;
  }
  return -1;
}

bool Esc::pdi_read_fast(std::uint16_t address, std::span<std::uint8_t> out) noexcept {
  const std::uint32_t end = address + static_cast<std::uint32_t>(out.size());
  if (out.empty()) return false;
  if (address >= reg::kAlEventRequest && end <= reg::kAlEventRequest + sizeof(std::uint32_t)) {
    const std::uint32_t v = al_event() >> (8 * (address - reg::kAlEventRequest));
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = static_cast<std::uint8_t>(v >> (8 * i));
    return true;
  }
  if (address >= reg::kSyncManagerBase && end <= reg_layout::kSmEnd) {
    // The SM registers (a firmware's look at SM2's status every cycle, the
    // mailbox's at SM0/SM1 at every poll): stored bytes, of which a PDI read
    // of status or activate acknowledges, as reg_read_byte does byte by byte.
    std::memcpy(out.data(), mem_.get() + address, out.size());
    pdi_sm_registers_read(address, end);
    return true;
  }
  const int n = pdi_sm_for(address, end);
  if (n < 0) return pdi_read_dc(address, end, out);
  SmSignals sig;
  if (!sms_[n].read(Side::Pdi, address, out, sig)) std::fill(out.begin(), out.end(), std::uint8_t{0});
  apply(static_cast<unsigned>(n), sig);
  return true;
}

// Inside the DC block (a firmware's SYNC acknowledge, 0x098E, every DC
// cycle): the DC unit's read, as mem_read's reg_read takes it. Out of
// pdi_read_fast's line, asked last: its other reads keep their code.
bool Esc::pdi_read_dc(std::uint32_t address, std::uint32_t end, std::span<std::uint8_t> out) noexcept {
  if (address < reg::kDcBase || end > reg::kDcEnd || !config_.dc) return false;
  dc_.read(static_cast<std::uint16_t>(address - reg::kDcBase), out, now_, Side::Pdi);
  return true;
}

// What a PDI read of SM registers [address, end) acknowledges: the status
// and activate bytes it covers, as reg_read_byte takes them one by one.
void Esc::pdi_sm_registers_read(std::uint32_t address, std::uint32_t end) noexcept {
  const std::uint32_t first = (address - reg::kSyncManagerBase) / reg::kSyncManagerStride;
  const std::uint32_t last = (end - 1 - reg::kSyncManagerBase) / reg::kSyncManagerStride;
  for (std::uint32_t n = first; n <= last; ++n) {
    const std::uint32_t base = reg::kSyncManagerBase + n * reg::kSyncManagerStride;
    for (const unsigned off : {reg::sm::kStatus, reg::sm::kActivate}) {
      if (address <= base + off && base + off < end) pdi_sm_read_acknowledge(n, off);
    }
  }
}

bool Esc::pdi_write_fast(std::uint16_t address, std::span<const std::uint8_t> in) noexcept {
  if (in.empty()) return false;
  const int n = pdi_sm_for(address, address + static_cast<std::uint32_t>(in.size()));
  if (n < 0) return false;
  SmSignals sig;
  (void)sms_[n].write(Side::Pdi, address, in, sig);
  apply(static_cast<unsigned>(n), sig);
  return true;
}

// Whole-buffer accesses in place (Pdi::read_buffer / write_buffer_begin /
// write_buffer_commit): the same steps as read()/write() on the fast path -
// timers, the SM's buffered rules, its signals, the PDI watchdog - with the
// copy between ESC memory and the caller's bytes left out. The bytes of a
// 3-buffer the PDI holds do not move until its next access (the ECAT side
// writes another buffer, and time changes none), which is what makes the
// view valid until then; a write's bytes lie in the buffer write() would
// copy them into, which only the commit's exchange hands to the master.
// tests/esc/esc_pdi_fast_path_test.cpp compares them with the checked path.
int Esc::pdi_find_in_place_sm(std::uint16_t address, std::size_t n, bool write) noexcept {
  if (!config_.fast_paths || n == 0) return -1;
  const int sm = pdi_sm_for(address, address + static_cast<std::uint32_t>(n));
  if (sm < 0 || !sms_[sm].buffered(Side::Pdi, write)) return -1;
  pdi_buffer_hints_[write ? 1 : 0] = {address, static_cast<std::uint32_t>(n), sm};
  return sm;
}

std::span<const std::uint8_t> Esc::read_buffer(std::uint16_t address, std::span<std::uint8_t> scratch) noexcept {
  touch();
  const int sm = pdi_in_place_sm(address, scratch.size(), false);
  if (sm < 0) {
    read(address, scratch);
    return scratch;
  }
  const Nanoseconds t = pdi_now();
  run_timers(t);
  now_ = t;
  SmSignals sig;
  const auto n = static_cast<unsigned>(sm);
  const std::uint32_t at = sms_[n].buffered_read(Side::Pdi, address, scratch.size(), sig);
  apply(n, sig);
  pdi_watchdog_trigger(t);
  if (at + scratch.size() <= sms_[n].memory_end()) return {mem_.get() + at, scratch.size()};
  sm_detail::copy_out(mem_.get(), sms_[n].memory_end(), at, scratch);
  return scratch;
}

std::span<std::uint8_t> Esc::write_buffer_begin(std::uint16_t address, std::span<std::uint8_t> scratch) noexcept {
  touch();
  const int sm = pdi_in_place_sm(address, scratch.size(), true);
  if (sm < 0) return scratch;
  const std::uint32_t at = sms_[static_cast<unsigned>(sm)].write_position(address);
  if (at + scratch.size() > sms_[static_cast<unsigned>(sm)].memory_end()) return scratch;
  return {mem_.get() + at, scratch.size()};
}

void Esc::write_buffer_commit(std::uint16_t address, std::span<const std::uint8_t> bytes) noexcept {
  touch();
  const int sm = pdi_in_place_sm(address, bytes.size(), true);
  if (sm < 0 || bytes.data() != mem_.get() + sms_[static_cast<unsigned>(sm)].write_position(address)) {
    write(address, bytes);  // the caller's scratch (or, against the contract, a stale place)
    return;
  }
  const Nanoseconds t = pdi_now();
  run_timers(t);
  now_ = t;
  SmSignals sig;
  const auto n = static_cast<unsigned>(sm);
  (void)sms_[n].buffered_write(Side::Pdi, address, bytes.size(), sig);
  apply(n, sig);
  pdi_watchdog_trigger(t);
}

// Any PDI access restarts the PDI watchdog and shows it in DL status bit 1
// (written only when it did not: Watchdogs::pdi_status_shown).
void Esc::pdi_watchdog_trigger(Nanoseconds t) noexcept {
  watchdogs_.trigger_pdi(t);
  refresh_watchdog_timer();
  if (!watchdogs_.pdi_status_shown()) [[unlikely]] {
    std::uint8_t* p = mem_.get() + reg::kDlStatus;
    store_le(p, static_cast<std::uint16_t>(load_le<std::uint16_t>(p) | bits::kDlPdiWatchdogOk));
    watchdogs_.set_pdi_status_shown();
  }
}

// 0x0400, 0x0410 and 0x0420 are read here only: a trigger takes the
// timeouts Watchdogs keeps.
void Esc::watchdog_times_written() noexcept {
  const std::uint8_t* m = mem_.get();
  watchdogs_.set_times(load_le<std::uint16_t>(m + reg::kWatchdogDivider),
                       load_le<std::uint16_t>(m + reg::kWatchdogTimePdi),
                       load_le<std::uint16_t>(m + reg::kWatchdogTimeProcessData));
}

// --- Time ---------------------------------------------------------------------------

// The frames of the line that passed this ESC by since it last looked
// (esc/pass_hook.hpp): its latest access is the latest frame's arrival,
// and its DC unit has seen that frame's return. The segment keeps frames
// whose times could leave a gap (fewer ESCs reached, earlier start) from
// reaching this point unapplied (Segment::record_pass), so the latest one suffices.
void Esc::apply_pass() noexcept {
  const LinePass& p = *hook_.line;
  if (p.routes != nullptr) [[unlikely]] {
    apply_route_passes(p);
    return;
  }
  hook_.synced = p.frame;
  if (hook_.index >= p.reached) return;
  now_ = p.at(hook_.index);
  dc_.note_time(p.latest(hook_.index));
}

// A tree or ring: the latest frame of each master port that passed this
// ESC by since it last looked, in the order they were sent. Each one's
// times stand for the earlier frames of its port (the segment takes every
// ESC's times in before a port's frame takes another way or starts
// earlier: Segment::record_route_pass); the processing unit's time is the
// access time of the last frame that had one here, the DC unit keeps the
// latest time seen.
void Esc::apply_route_passes(const LinePass& p) noexcept {
  const std::uint64_t synced = hook_.synced;
  hook_.synced = p.frame;
  const RoutePass* a = &p.routes[0];
  const RoutePass* b = &p.routes[1];
  if (b->frame < a->frame) std::swap(a, b);
  for (const RoutePass* r : {a, b}) {
    if (r->frame <= synced || r->unit_at == nullptr) continue;
    const Nanoseconds unit = r->unit_at[hook_.index];
    if (unit != RoutePass::kNoTime) now_ = r->start + unit;
    const Nanoseconds seen = r->seen_at[hook_.index];
    if (seen != RoutePass::kNoTime) dc_.note_time(r->start + seen);
  }
}

Nanoseconds Esc::advance(Nanoseconds now) noexcept {
  touch();
  run_timers(now);
  now_ = now;
  const Nanoseconds dc = dc_.advance(now);
  // next_timer_ is the earliest of the watchdogs' and the SII's deadlines
  // (refresh_timers), kNoDeadline when neither runs.
  return std::min(next_timer_, dc);
}



// Nothing is due before next_timer_: most frames skip this entirely.
void Esc::run_due_timers(Nanoseconds now) noexcept {
  sii_action(sii_.poll(now));
  const Watchdogs::Expired e = watchdogs_.check(now);
  std::uint8_t* m = mem_.get();
  if (e.process_data) {
    // Section II 0x0440: status 0, counter +1 (saturating), AL event bit 6;
    // digital outputs 0x0F00-0x0F03 go to 0. The AL state is left to the
    // application (INF-WD; the ESM reacts with SafeOp + 0x001B).
    m[reg::kWatchdogStatusProcessData] = 0;
    if (m[reg::kWatchdogCounterProcessData] < bits::kCounterMax) ++m[reg::kWatchdogCounterProcessData];
    std::memset(m + reg::kDigitalIoOutput, 0, bits::kDigitalOutputEnd - reg::kDigitalIoOutput);
    set_al_event(bits::kAlEventWatchdog);
  }
  if (e.pdi) {
    if (m[reg::kWatchdogCounterPdi] < bits::kCounterMax) ++m[reg::kWatchdogCounterPdi];
    store_le(m + reg::kDlStatus,
             static_cast<std::uint16_t>(register_u16(reg::kDlStatus) & ~bits::kDlPdiWatchdogOk));
    set_ecat_event(bits::kEcatEventDlStatus);
  }
  refresh_timers();
}

void Esc::sii_action(SiiInterface::Action a) noexcept {
  if (a == SiiInterface::Action::Reload) {
    load_eeprom(false);
    update_dl_status();  // bit 0 follows the checksum
  }
}

// --- Ports and DL status ------------------------------------------------------------

std::uint32_t Esc::loop_control(unsigned port) const noexcept {
  return (dl_control() >> (bits::kDlLoopShift + 2 * port)) & bits::kDlLoopMask;
}

// A link lost on a port in Auto or Auto-close counts in 0x0310+port
// (saturating; Section II 0x0310, Section I §14 error counters); Auto-close
// keeps the port closed until the master writes the loop control again or a
// valid frame arrives at it (Section I §3.4 Figure 4, "closed wait").
void Esc::set_link(unsigned port, bool l) noexcept {
  if (port >= kMaxPorts) return;
  touch();
  const bool was = link_[port];
  link_[port] = l && present_[port];
  if (was && !link_[port]) {
    const std::uint32_t loop = loop_control(port);
    if (loop == bits::kLoopAuto || loop == bits::kLoopAutoClose) {
      std::uint8_t& c = mem_[reg::kLostLinkCounter + port];
      if (c < bits::kCounterMax) ++c;
    }
    if (loop == bits::kLoopAutoClose) closed_wait_[port] = true;
  }
  update_ports();
  update_dl_status();
}

void Esc::frame_at_closed_port(unsigned port) noexcept {
  touch();
  if (port >= kMaxPorts || !closed_wait_[port] || !link_[port]) return;
  closed_wait_[port] = false;
  update_ports();
  update_dl_status();
}

// Writing the loop configuration again (0x0101) opens Auto-close ports in
// "closed wait" that have a link (Section I §3.4).
void Esc::loop_control_written() noexcept {
  for (unsigned p = 0; p < kMaxPorts; ++p) {
    if (loop_control(p) == bits::kLoopAutoClose) closed_wait_[p] = false;
  }
}

// Loop control per port (0x0100 bits 8+2n, Section I §3.4): Auto follows the
// link; Auto-close too, except in "closed wait"; open/closed are forced.
// A port that does not exist is closed.
void Esc::update_ports() noexcept {
  ++address_epoch_;
  for (unsigned p = 0; p < kMaxPorts; ++p) {
    bool open = false;
    if (present_[p]) {
      const std::uint32_t loop = loop_control(p);
      open = loop == bits::kLoopOpen || (loop == bits::kLoopAuto && link_[p]) ||
             (loop == bits::kLoopAutoClose && link_[p] && !closed_wait_[p]);
    }
    port_open_[p] = open;
  }
  // The line path (Section I §3.2 order 0 -> PU -> 3 -> 1 -> 2 -> 0): with
  // ports 2 and 3 closed the frame goes out of port 1 when it is open, and
  // otherwise back; an open port 2/3 has no neighbour in a line.
  if (port_open_[2] || port_open_[3]) {
    line_route_ = LineRoute::Lost;
  } else if (port_open_[1]) {
    line_route_ = link_[1] ? LineRoute::Down : LineRoute::Lost;
  } else {
    line_route_ = LineRoute::Back;
  }
}

// Enabled SMs (Section I §8): the ones whose area the memory path guards;
// and the SMs whose bytes are plain memory or registers and that only
// trigger the process-data watchdog: 1-byte SMs (0x0802) and SMs over the
// digital output registers.
void Esc::update_sm_guards() noexcept {
  sm_enabled_ = 0;
  sm_watchdog_only_ = 0;
  pdi_buffer_hints_ = {};  // an SM register changed (pdi_in_place_sm)
  for (unsigned n = 0; n < config_.sync_manager_count; ++n) {
    if (sms_[n].enabled()) sm_enabled_ |= 1u << n;
    if (sms_[n].watchdog_trigger_only() || sms_[n].watchdog_trigger_on_registers()) sm_watchdog_only_ |= 1u << n;
  }
  update_fmmus();  // their routes depend on the SMs
}

void Esc::update_dl_status() noexcept {
  std::uint8_t* m = mem_.get();
  const std::uint16_t old = load_le<std::uint16_t>(m + reg::kDlStatus);
  std::uint16_t s = old & bits::kDlPdiWatchdogOk;
  if ((load_le<std::uint16_t>(m + reg::kEepromControlStatus) & sii_bits::kNotLoaded) == 0) {
    s |= bits::kDlPdiOperational;
  }
  if (m[reg::kEscConfiguration] & bits::kEscConfigEnhancedLink) s |= bits::kDlEnhancedLinkDetection;
  for (unsigned p = 0; p < kMaxPorts; ++p) {
    if (link_[p]) s |= static_cast<std::uint16_t>(1u << (bits::kDlPhysicalLinkShift + p));
    if (!port_open(p)) s |= static_cast<std::uint16_t>(1u << (bits::kDlLoopClosedShift + 2 * p));
    if (link_[p]) s |= static_cast<std::uint16_t>(1u << (bits::kDlCommunicationShift + 2 * p));
  }
  store_le(m + reg::kDlStatus, s);
  if (s != old) set_ecat_event(bits::kEcatEventDlStatus);
}

namespace {
void saturating_increment(std::uint8_t& c) noexcept {
  if (c < bits::kCounterMax) ++c;
}
}  // namespace

void Esc::count_rx_error(unsigned port, bool forwarded) noexcept {
  count_port_error(port, forwarded ? PortError::Forwarded : PortError::InvalidFrame);
}

// Section I §14.1 Table 51 (auto-forwarder: 0x0300+2n original error,
// 0x0308+n forwarded error; physical layer: 0x0301+2n) and §14.2 (an error
// is counted as the port's own only by the first ESC that finds it).
void Esc::count_port_error(unsigned port, PortError error) noexcept {
  if (port >= kMaxPorts) return;
  touch();
  std::uint8_t* m = mem_.get();
  switch (error) {
    case PortError::Forwarded:
      saturating_increment(m[reg::kForwardedRxErrorCounter + port]);
      break;
    case PortError::PhysicalLayer:
      saturating_increment(m[reg::kRxErrorCounter + 2 * port + 1]);
      saturating_increment(m[reg::kRxErrorCounter + 2 * port]);  // "includes RX errors"
      break;
    case PortError::InvalidFrame:
      saturating_increment(m[reg::kRxErrorCounter + 2 * port]);
      break;
  }
}

void Esc::count_processing_unit_error() noexcept { saturating_increment(mem_[reg::kProcessingUnitErrorCounter]); }

void Esc::count_pdi_error(std::uint8_t code) noexcept {
  saturating_increment(mem_[reg::kPdiErrorCounter]);
  mem_[reg::kPdiErrorCode] = code;
}

}  // namespace ecat::esc
