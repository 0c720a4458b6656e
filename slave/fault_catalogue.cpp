#include "slave/fault_catalogue.hpp"

#include <algorithm>
#include <array>

#include <fmt/format.h>

#include "common/le.hpp"
#include "ds402/drive.hpp"
#include "esc/registers.hpp"
#include "esc/sii_interface.hpp"
#include "od/firmware.hpp"
#include "slave/faults/esm_guard.hpp"
#include "slave/faults/frame_faults.hpp"
#include "slave/faults/mailbox_faults.hpp"
#include "slave/faults/reply_faults.hpp"
#include "slave/faults/dc_faults.hpp"
#include "slave/faults/drive_faults.hpp"

namespace ecat::slave {

namespace {

// --- The catalogue (docs/faults.md has the same rows, with the spec clauses) ---

constexpr std::array kNoParams = std::array<FaultParam, 0>{};
constexpr std::array kCorruptParams{
    FaultParam{"count", "frames the cable corrupts (1..1000000, default 1)", false},
    FaultParam{"rx_error", "1: a PHY symbol error (also counted in 0x0301+2n) instead of a bad FCS (default 0)", false},
};
constexpr std::array kDropParams{
    FaultParam{"count", "frames lost (0 = every frame until cleared; default 1)", false},
    FaultParam{"after", "1: lost on the way back, after the slaves processed it (default 0: before the first slave; "
                        "always 1 with a slave)",
               false},
};
constexpr std::array kWkcParams{
    FaultParam{"command", "datagram command (ETG.1000.4 Table: 1 APRD .. 12 LRW .. 14 FRMW)", true},
    FaultParam{"offset", "added to its working counter (-65535..65535, not 0; modulo 2^16)", true},
    FaultParam{"count", "frames with that command it changes (0 = until cleared; default 0)", false},
};
constexpr std::array kAlErrorParams{
    FaultParam{"code", "AL status code 0x0134 (0x0001..0xFFFF; 0x8000.. vendor)", true},
    FaultParam{"state", "state the error forces (1 Init, 2 PreOp, 4 SafeOp; default: the code's, ETG.1000.6 Table 11)",
               false},
};
constexpr std::array kRefuseParams{
    FaultParam{"code", "AL status code of the refusal (0x0001..0xFFFF)", true},
    FaultParam{"state", "refuse only the transition into this state (2 PreOp, 3 Boot, 4 SafeOp, 8 Op; default: "
                        "the next upward one)",
               false},
    FaultParam{"count", "transitions refused (1..1000, default 1)", false},
};
constexpr std::array kDriveParams{
    FaultParam{"code", "error code 603Fh and EMCY (0x0001..0xFFFF, e.g. 0x2310 over-current)", true},
    FaultParam{"error_register", "1001h bits besides generic (0..255; default by code class, CiA 301 Table 21)",
               false},
    FaultParam{"axis", "axis of a multi-axis drive (0-based, default 0)", false},
};

constexpr std::array kMailboxErrorParams{
    FaultParam{"code", "mailbox error code (1 syntax .. 8 invalid size, ETG.1000.4 Table 30; default 2 unsupported "
                       "protocol)",
               false},
    FaultParam{"count", "requests answered so (0 = every one until cleared; default 0)", false},
};
constexpr std::array kReplyLimitParams{
    FaultParam{"bytes", "largest reply payload, CoE header included (16..65535)", true},
};
constexpr std::array kStormParams{
    FaultParam{"count", "emergencies sent (1..1000000000, default 100)", false},
    FaultParam{"code", "their error code (0..0xFFFF, default 0xFF00)", false},
    FaultParam{"error_register", "their error register byte (0..255, default 0x80)", false},
};

constexpr std::array kDelayParams{
    FaultParam{"us", "how long each reply is held (1..10000000 us)", true},
    FaultParam{"count", "replies held (0 = every one until cleared; default 0)", false},
};
constexpr std::array kRepeatParams{
    FaultParam{"count", "replies it acts on (0 = every one until cleared; default 1)", false},
};

constexpr std::array kDcDriftParams{
    FaultParam{"ppm", "added to the oscillator's error from now on (-5000..5000, not 0; the ESC corrects +-1000)", true},
};
constexpr std::array kDcJumpParams{
    FaultParam{"ns", "the local time steps by this once (signed ns, not 0)", true},
};
constexpr std::array kAxisParams{
    FaultParam{"axis", "axis of a multi-axis drive (0-based, default 0)", false},
};
constexpr std::array kLimitSwitchParams{
    FaultParam{"side", "0: negative limit (60FDh bit 0), 1: positive limit (bit 1)", true},
    FaultParam{"axis", "axis of a multi-axis drive (0-based, default 0)", false},
};

constexpr std::array kKinds{
    FaultKind{"link_cut", "the cable on that port is cut: both ends lose the link (DL status 0x0110, lost-link "
                          "counter 0x0310+n), the port loops back, slaves behind it vanish from the working counters",
              true, true, kNoParams},
    FaultKind{"corrupt_frames", "the cable on that port corrupts the next frames: RX error counters 0x0300+ as "
                                "silicon counts them, the master gets them with a bad FCS (lost)",
              true, true, kCorruptParams},
    FaultKind{"drop_frames", "the next frames are lost (with a slave: those carrying an APxx/FPxx datagram for it, "
                             "after it processed them): the master times out",
              false, false, kDropParams, true},
    FaultKind{"wkc_offset", "the working counter of every datagram of one command type comes back off by an offset",
              false, false, kWkcParams},
    FaultKind{"al_error", "the slave latches an AL error: AL status 0x0130 = forced state | ErrInd, 0x0134 = code; "
                          "while engaged, requests above that state are refused with the code",
              true, false, kAlErrorParams},
    FaultKind{"refuse_transition", "the next upward transitions are refused: AL status stays | ErrInd, 0x0134 = code",
              true, false, kRefuseParams},
    FaultKind{"watchdog_expiry", "the process-data watchdog expires: 0x0440 = 0, 0x0442 + 1, outputs safe, SafeOp | "
                                 "ErrInd with 0x001B; while engaged, Op is refused with 0x001B",
              true, false, kNoParams},
    FaultKind{"power_cycle", "the slave loses power: its cables go down (it and the slaves behind it vanish, the "
                             "neighbours count a lost link); cleared, it powers up: Init, station address 0, power-up "
                             "registers, SII loaded from its EEPROM, firmware restarted",
              true, false, kNoParams},
    FaultKind{"sii_bad_checksum", "the SII checksum (word 7) in the EEPROM goes bad and the EEPROM reloads: 0x0502 "
                                  "bits 11 (checksum error) and 12 (not loaded), 0x0110 bit 0 = 0; cleared, restored "
                                  "and reloaded",
              true, false, kNoParams},
    FaultKind{"sii_busy_stuck", "the SII interface sticks busy: the master's next EEPROM command leaves 0x0502 bit "
                                "15 set and every later one is ignored (SII timeouts); cleared, the command completes",
              true, false, kNoParams},
    FaultKind{"mailbox_counter_frozen", "the slave's mailbox replies stop incrementing their counter (header byte 5 "
                                        "bits 4-6): each carries the counter of the one before",
              true, false, kNoParams},
    FaultKind{"mailbox_held", "the slave takes mailbox requests but no reply or emergency goes into SM1 (0x080D bit 3 "
                              "stays clear, the master times out); cleared, the held replies go out in order",
              true, false, kNoParams},
    FaultKind{"drive_fault", "the CiA 402 drive faults: statusword Fault, 603Fh = code, 1001h, an EMCY with the code; "
                             "fault reset works again once cleared",
              true, false, kDriveParams},
    FaultKind{"mailbox_error_replies", "every mailbox request is answered with a mailbox error (type 0, service 01h, "
                                       "the code) instead of being executed",
              true, false, kMailboxErrorParams},
    FaultKind{"mailbox_reply_limit", "no mailbox reply payload is longer than `bytes`: SDO uploads go segmented, SDO "
                                     "information comes in more fragments",
              true, false, kReplyLimitParams},
    FaultKind{"emergency_storm", "the slave sends `count` emergencies back to back, one each time SM1 is free and no "
                                 "request waits for its reply",
              true, false, kStormParams},
    FaultKind{"sdo_upload_truncated", "a segmented SDO upload ends after its first segment: that segment carries the "
                                      "last-segment bit though bytes of the announced size remain",
              true, false, kNoParams},
    FaultKind{"unplug", "the slave is unplugged with its power kept: every cable of it goes down (it and the slaves "
                        "behind it vanish, the neighbours count a lost link) while its ESC and firmware run on; "
                        "cleared, it is plugged back as it is (hot connect: its station address and state kept)",
              true, false, kNoParams},
    FaultKind{"delay_frames", "every reply is held `us` microseconds before it goes back to the master (a master "
                              "with a shorter timeout sees it lost, then a stale frame)",
              false, false, kDelayParams},
    FaultKind{"duplicate_frames", "every reply goes back twice: the master reads a stale copy after the real one",
              false, false, kRepeatParams},
    FaultKind{"replay_frames", "every reply is replaced by the reply before it: the master reads a stale frame and "
                               "misses its own",
              false, false, kRepeatParams},
    FaultKind{"sdo_toggle_wrong", "every SDO segment reply (upload and download) carries the toggle bit the request "
                                  "did not have",
              true, false, kNoParams},
    FaultKind{"dc_drift", "the slave's oscillator runs `ppm` off from now on: the time loop corrects it within +-1000 "
                          "ppm, beyond that the system-time difference 0x092C grows",
              true, false, kDcDriftParams},
    FaultKind{"dc_time_jump", "the slave's local time jumps by `ns` once: the system-time difference 0x092C follows",
              true, false, kDcJumpParams},
    FaultKind{"sync0_stopped", "the SYNC unit puts out no SYNC0 though 0x0981 stays activated: a DC slave in SafeOp/Op "
                               "goes to SafeOp | ErrInd with 0x0034 after 3 cycles",
              true, false, kNoParams},
    FaultKind{"limit_switch", "a limit switch input (60FDh bit 0/1) goes active: statusword bit 11; motion into it is "
                              "the limit-switch fault FF04h/FF03h with its EMCY",
              true, false, kLimitSwitchParams},
    FaultKind{"quick_stop_input", "the drive's quick-stop input goes active: quick stop per 605Ah (Quick stop active, "
                                  "then Switch on disabled), no enable while it is active",
              true, false, kAxisParams},
    FaultKind{"sto", "safe torque off: no torque at once, Fault with 603Fh = 5441h and its EMCY; fault reset refused "
                     "while engaged",
              true, false, kAxisParams},
    FaultKind{"brake_stuck", "the holding brake does not release: the motor cannot move, so under motion the following "
                             "error reaches 6065h and the drive faults with 8611h",
              true, false, kAxisParams},
};

// The state an AL status code forces when raised at run time
// (shared/spec/esm-al-codes.md §4, ETG.1000.6 Table 11 "resulting state").
esc::AlState forced_state(std::uint16_t code) noexcept {
  switch (code) {
    case 0x0014:  // no valid firmware
    case 0x0015:  // invalid mailbox configuration (Boot)
    case 0x0016:  // invalid mailbox configuration (PreOp)
      return esc::AlState::Init;
    case 0x001E:  // invalid input configuration
    case 0x001F:  // invalid watchdog configuration
    case 0x0024:
    case 0x0025:
    case 0x0026:
    case 0x0027:
    case 0x0028:
    case 0x0029:
    case 0x002A:  // background watchdog
    case 0x0036:
    case 0x0037:
      return esc::AlState::PreOp;
    default:  // 0x001A sync, 0x001B SM watchdog, 0x0030 DC sync configuration, ... and vendor codes
      return esc::AlState::SafeOp;
  }
}

std::optional<esc::AlState> al_state_of(std::int64_t v) noexcept {
  switch (v) {
    case 1:
      return esc::AlState::Init;
    case 2:
      return esc::AlState::PreOp;
    case 3:
      return esc::AlState::Bootstrap;
    case 4:
      return esc::AlState::SafeOp;
    case 8:
      return esc::AlState::Op;
    default:
      return std::nullopt;
  }
}

std::string known_kinds() {
  std::string s;
  for (const FaultKind& k : kKinds) s += (s.empty() ? "" : ", ") + std::string(k.name);
  return s;
}

std::int64_t param(const FaultRequest& r, const char* name, std::int64_t fallback) {
  const auto it = r.params.find(name);
  return it == r.params.end() ? fallback : it->second;
}

}  // namespace

// --- State of the engaged faults ---

struct FaultCatalogue::Impl {
  enum class Where : std::uint8_t {
    Link,
    Corrupt,
    Frame,
    Esm,
    Drive,
    Power,
    SiiChecksum,
    SiiBusy,
    Mailbox,
    Reply,
    Unplug,
    Dc,
    DriveInput,
  };
  struct Record {
    EngagedFault fault;
    Where where = Where::Link;
    std::size_t slave = 0;
    unsigned port = 0;
    ds402::Drive* drive = nullptr;
    std::vector<unsigned> ports_cut;  // Power, Unplug: the cables it took down
    std::uint8_t saved_byte = 0;      // SiiChecksum: the EEPROM byte it replaced
    faults::MailboxFault mailbox = faults::MailboxFault::CounterFrozen;
    faults::DcFault dc = faults::DcFault::Drift;  // Dc
    faults::DcFaultState dc_state;                 // Dc
    faults::DriveInputFault input;                 // DriveInput (with drive)
  };
  std::map<FaultId, Record> records;
  FaultId next = 1;
  faults::FrameFaults frames;
  faults::ReplyFaults replies;
  // Per slave, created when a state fault first needs it, registered on its ESM.
  std::vector<std::unique_ptr<faults::EsmGuard>> guards;
};

FaultCatalogue::FaultCatalogue(Chain& chain) : chain_(chain), impl_(std::make_unique<Impl>()) {}

FaultCatalogue::~FaultCatalogue() {
  observer_ = nullptr;
  clear_all();
  for (std::size_t i = 0; i < impl_->guards.size(); ++i) {
    if (impl_->guards[i]) (void)chain_[i].firmware().esm().remove_hooks(*impl_->guards[i]);
  }
}

std::span<const FaultKind> FaultCatalogue::kinds() noexcept { return kKinds; }

const FaultKind* FaultCatalogue::find_kind(std::string_view name) noexcept {
  for (const FaultKind& k : kKinds) {
    if (k.name == name) return &k;
  }
  return nullptr;
}

std::vector<EngagedFault> FaultCatalogue::engaged() const {
  std::vector<EngagedFault> out;
  out.reserve(impl_->records.size());
  for (const auto& [id, r] : impl_->records) out.push_back(r.fault);
  return out;
}

namespace {

// The checks every kind shares: slave, port, parameter names and presence.
Expected<void, std::string> check_shape(const FaultKind& k, const FaultRequest& r, const Chain& chain) {
  if (r.slave) {
    if (!k.needs_slave && !k.takes_slave) return fail(fmt::format("{}: takes no slave", k.name));
    if (*r.slave >= chain.size()) {
      return fail(fmt::format("{}: no slave {} (0-based; the chain has {})", k.name, *r.slave, chain.size()));
    }
  } else if (k.needs_slave) {
    return fail(fmt::format("{}: needs a slave", k.name));
  }
  if (r.port) {
    if (!k.needs_port) return fail(fmt::format("{}: takes no port", k.name));
    if (*r.port >= esc::kMaxPorts) return fail(fmt::format("{}: no port {} (ports are 0..3)", k.name, *r.port));
  } else if (k.needs_port) {
    return fail(fmt::format("{}: needs a port", k.name));
  }
  for (const auto& param : r.params) {
    // (a named variable, not a structured binding: clang 14 cannot capture those)
    const std::string& name = param.first;
    const bool known =
        std::any_of(k.params.begin(), k.params.end(), [&](const FaultParam& p) { return p.name == name; });
    if (!known) {
      std::string takes;
      for (const FaultParam& p : k.params) takes += (takes.empty() ? "" : ", ") + std::string(p.name);
      return fail(fmt::format("{}: unknown parameter '{}' (takes: {})", k.name, name, takes.empty() ? "none" : takes));
    }
  }
  for (const FaultParam& p : k.params) {
    if (p.required && !r.params.contains(std::string(p.name))) {
      return fail(fmt::format("{}: parameter '{}' is required ({})", k.name, p.name, p.meaning));
    }
  }
  return {};
}

Expected<void, std::string> in_range(std::string_view kind, const FaultRequest& r, const char* name, std::int64_t lo,
                                     std::int64_t hi) {
  const auto it = r.params.find(name);
  if (it == r.params.end() || (it->second >= lo && it->second <= hi)) return {};
  return fail(fmt::format("{}: {} = {} is out of range ({}..{})", kind, name, it->second, lo, hi));
}

}  // namespace

Expected<FaultId, std::string> FaultCatalogue::engage(const FaultRequest& request) {
  const FaultKind* kind = find_kind(request.kind);
  if (kind == nullptr) return fail(fmt::format("unknown fault kind '{}' (known: {})", request.kind, known_kinds()));
  if (auto ok = check_shape(*kind, request, chain_); !ok) return fail(ok.error());
  const std::string_view k = kind->name;
  Impl& im = *impl_;
  Impl::Record rec;
  rec.fault.request = request;
  rec.slave = request.slave.value_or(0);
  rec.port = request.port.value_or(0);
  const FaultId id = im.next;
  rec.fault.id = id;
  auto same_place = [&](Impl::Where w) -> std::optional<FaultId> {
    for (const auto& [other, r] : im.records) {
      if (r.where == w && r.slave == rec.slave && r.port == rec.port) return other;
    }
    return std::nullopt;
  };
  // The CiA 402 drive of an axis of the slave (drive_fault and the drive's inputs).
  auto drive_of = [this](std::string_view kind_name, std::size_t slave,
                         std::size_t axis) -> Expected<ds402::Drive*, std::string> {
    Application* app = chain_[slave].firmware().application();
    ds402::Drive* d = app ? app->drive(axis) : nullptr;
    if (d == nullptr) {
      return fail(fmt::format("{}: slave {} runs no CiA 402 drive{}", kind_name, slave,
                              axis == 0 ? "" : fmt::format(" with an axis {}", axis)));
    }
    return d;
  };
  // Firmware faults need the slave powered (power_cycle replaces its firmware).
  if (kind->needs_slave && k != "link_cut" && k != "corrupt_frames") {
    for (const auto& [other, r] : im.records) {
      if (r.where == Impl::Where::Power && r.slave == rec.slave) {
        return fail(fmt::format("{}: slave {} is powered off (fault {})", k, rec.slave, other));
      }
    }
  }
  // Each kind: check its values, then act (nothing changes before every check passed).
  if (k == "link_cut" || k == "corrupt_frames") {
    esc::Segment& seg = chain_.segment();
    if (!seg.peer(rec.slave, rec.port)) {
      return fail(fmt::format("{}: nothing is cabled on port {} of slave {}", k, rec.port, rec.slave));
    }
    if (k == "link_cut") {
      rec.where = Impl::Where::Link;
      if (auto other = same_place(rec.where)) return fail(fmt::format("{}: already cut by fault {}", k, *other));
      if (!seg.link_up(rec.slave, rec.port)) {
        return fail(fmt::format("{}: the cable on port {} of slave {} is already down", k, rec.port, rec.slave));
      }
      (void)seg.set_link(rec.slave, rec.port, false);
    } else {
      rec.where = Impl::Where::Corrupt;
      if (auto ok = in_range(k, request, "count", 1, 1'000'000); !ok) return fail(ok.error());
      if (auto ok = in_range(k, request, "rx_error", 0, 1); !ok) return fail(ok.error());
      if (auto other = same_place(rec.where)) {
        return fail(fmt::format("{}: that cable already corrupts frames (fault {})", k, *other));
      }
      const auto fault = param(request, "rx_error", 0) != 0 ? esc::Segment::CableFault::RxError
                                                            : esc::Segment::CableFault::Crc;
      (void)seg.corrupt_link(rec.slave, rec.port, static_cast<unsigned>(param(request, "count", 1)), fault);
      ++frame_faults_;
    }
  } else if (k == "drop_frames") {
    if (auto ok = in_range(k, request, "count", 0, 1'000'000'000); !ok) return fail(ok.error());
    if (auto ok = in_range(k, request, "after", 0, 1); !ok) return fail(ok.error());
    faults::DropRule d;
    d.id = id;
    d.left = static_cast<std::uint64_t>(param(request, "count", 1));
    d.until_cleared = d.left == 0;
    d.after = param(request, "after", 0) != 0;
    if (request.slave) {
      d.position = static_cast<std::uint16_t>(*request.slave);
      d.station = load_le<std::uint16_t>(chain_[*request.slave].esc().memory() + esc::reg::kConfiguredStationAddress);
      d.after = true;
    }
    rec.where = Impl::Where::Frame;
    im.frames.add(d);
    ++frame_faults_;
  } else if (k == "wkc_offset") {
    if (auto ok = in_range(k, request, "command", 1, kLastCommand); !ok) return fail(ok.error());
    if (auto ok = in_range(k, request, "offset", -65535, 65535); !ok) return fail(ok.error());
    if (auto ok = in_range(k, request, "count", 0, 1'000'000'000); !ok) return fail(ok.error());
    if (param(request, "offset", 0) == 0) return fail(fmt::format("{}: offset 0 changes nothing", k));
    faults::WkcRule w;
    w.id = id;
    w.command = static_cast<Command>(param(request, "command", 0));
    w.offset = static_cast<std::int32_t>(param(request, "offset", 0));
    w.left = static_cast<std::uint64_t>(param(request, "count", 0));
    w.until_cleared = w.left == 0;
    rec.where = Impl::Where::Frame;
    im.frames.add(w);
    ++frame_faults_;
  } else if (k == "al_error" || k == "refuse_transition" || k == "watchdog_expiry") {
    VirtualSlave& s = chain_[rec.slave];
    if (!od::runs_firmware(s.device())) {
      return fail(fmt::format("{}: slave {} has no firmware (an ESC without PDI): no state machine", k, rec.slave));
    }
    rec.where = Impl::Where::Esm;
    if (auto ok = in_range(k, request, "code", 1, 0xFFFF); !ok) return fail(ok.error());
    if (auto ok = in_range(k, request, "count", 1, 1000); !ok) return fail(ok.error());
    std::optional<esc::AlState> state;
    if (request.params.contains("state")) {
      state = al_state_of(param(request, "state", 0));
      const bool al_error_state = state && *state != esc::AlState::Op && *state != esc::AlState::Bootstrap;
      if (k == "al_error" && !al_error_state) {
        return fail(
            fmt::format("{}: state {} is not 1 (Init), 2 (PreOp) or 4 (SafeOp)", k, param(request, "state", 0)));
      }
      if (k == "refuse_transition" && (!state || *state == esc::AlState::Init)) {
        return fail(
            fmt::format("{}: state {} is not an upward target (2, 3, 4 or 8)", k, param(request, "state", 0)));
      }
    }
    const Nanoseconds now = chain_.time_seen();
    if (k == "watchdog_expiry" && now == Nanoseconds::min()) {
      return fail(fmt::format("{}: the process-data watchdog of slave {} is not running (disabled, no SM "
                              "with its trigger written yet, or already expired)",
                              k, rec.slave));
    }
    esc::Esm& esm = s.firmware().esm();
    if (im.guards.size() < chain_.size()) im.guards.resize(chain_.size());  // slaves added after construction
    if (!im.guards[rec.slave]) {
      // A refusal used up (inside the firmware's poll) clears itself.
      auto g = std::make_unique<faults::EsmGuard>([this](faults::EsmGuard::Id spent) {
        try {
          (void)clear(spent);
        } catch (...) {  // an observer that throws: the fault is cleared all the same
        }
      });
      if (!esm.add_hooks(*g)) return fail(fmt::format("{}: slave {}: no free ESM hook slot", k, rec.slave));
      im.guards[rec.slave] = std::move(g);
      // Its callback reaches this catalogue from inside the firmware: no
      // firmware on a helper thread from now on (Chain::set_firmware_threads).
      chain_.keep_firmware_serial();
    }
    faults::EsmGuard& guard = *im.guards[rec.slave];
    if (k == "al_error") {
      const auto code = static_cast<std::uint16_t>(param(request, "code", 0));
      const esc::AlState forced = state.value_or(forced_state(code));
      esm.raise_error(static_cast<esc::AlStatusCode>(code), forced);
      guard.hold(id, forced, static_cast<esc::AlStatusCode>(code));
    } else if (k == "refuse_transition") {
      guard.refuse(id, state, static_cast<esc::AlStatusCode>(param(request, "code", 0)),
                   static_cast<unsigned>(param(request, "count", 1)));
    } else {
      if (!s.esc().expire_process_data_watchdog(now)) {
        return fail(fmt::format("{}: the process-data watchdog of slave {} is not running (disabled, no SM "
                                "with its trigger written yet, or already expired)",
                                k, rec.slave));
      }
      (void)chain_.poll(now);  // the ESC and the firmware react now
      guard.hold(id, esc::AlState::SafeOp, esc::AlStatusCode::SyncManagerWatchdog);
    }
  } else if (k == "power_cycle") {
    rec.where = Impl::Where::Power;
    for (const auto& [other, r] : im.records) {
      if (r.slave != rec.slave) continue;
      if (r.where == Impl::Where::Esm || r.where == Impl::Where::Drive || r.where == Impl::Where::Mailbox ||
          r.where == Impl::Where::Dc || r.where == Impl::Where::DriveInput) {
        return fail(fmt::format("{}: slave {} has fault {} ({}) engaged on its firmware: clear it first", k, rec.slave,
                                other, r.fault.request.kind));
      }
    }
    if (auto other = same_place(Impl::Where::Unplug)) {
      return fail(fmt::format("{}: slave {} is unplugged (fault {}): plug it back first", k, rec.slave, *other));
    }
    esc::Segment& seg = chain_.segment();
    for (unsigned p = 0; p < esc::kMaxPorts; ++p) {
      if (seg.peer(rec.slave, p) && seg.link_up(rec.slave, p)) rec.ports_cut.push_back(p);
    }
    for (unsigned p : rec.ports_cut) (void)seg.set_link(rec.slave, p, false);
  } else if (k == "sii_bad_checksum" || k == "sii_busy_stuck") {
    rec.where = k == "sii_busy_stuck" ? Impl::Where::SiiBusy : Impl::Where::SiiChecksum;
    if (auto other = same_place(rec.where)) return fail(fmt::format("{}: already engaged as fault {}", k, *other));
    esc::Esc& e = chain_[rec.slave].esc();
    if (rec.where == Impl::Where::SiiBusy) {
      e.set_sii_stuck(true, std::max(chain_.time_seen(), Nanoseconds{0}));
    } else {
      // Word 7's low byte: the CRC over words 0-6 (ETG.1000.6 §5.4), made wrong.
      const auto sii = e.config().sii.bytes();
      if (sii.size() < esc::kSiiConfigAreaBytes + 2) {
        return fail(fmt::format("{}: slave {} has no SII checksum", k, rec.slave));
      }
      const std::uint8_t crc = esc::sii_crc(sii.first(esc::kSiiConfigAreaBytes));
      auto bad = static_cast<std::uint8_t>(crc ^ 0xFF);
      const std::uint16_t high = static_cast<std::uint16_t>(sii[esc::kSiiConfigAreaBytes + 1] << 8);
      if ((high | bad) == esc::kSiiChecksumDisabled) bad = static_cast<std::uint8_t>(bad ^ 0x01);
      rec.saved_byte = e.patch_eeprom_and_reload(esc::kSiiConfigAreaBytes, bad).value_or(0);
    }
  } else if (k == "unplug") {
    rec.where = Impl::Where::Unplug;
    if (auto other = same_place(rec.where)) return fail(fmt::format("{}: already unplugged (fault {})", k, *other));
    esc::Segment& seg = chain_.segment();
    for (unsigned p = 0; p < esc::kMaxPorts; ++p) {
      if (seg.peer(rec.slave, p) && seg.link_up(rec.slave, p)) rec.ports_cut.push_back(p);
    }
    if (rec.ports_cut.empty()) {
      return fail(fmt::format("{}: slave {} has no cable with a link to pull", k, rec.slave));
    }
    for (unsigned p : rec.ports_cut) (void)seg.set_link(rec.slave, p, false);
  } else if (k == "delay_frames" || k == "duplicate_frames" || k == "replay_frames") {
    if (auto ok = in_range(k, request, "us", 1, 10'000'000); !ok) return fail(ok.error());
    if (auto ok = in_range(k, request, "count", 0, 1'000'000'000); !ok) return fail(ok.error());
    faults::ReplyRule rule;
    rule.id = id;
    rule.kind = k == "delay_frames"       ? faults::ReplyRule::Kind::Delay
                : k == "duplicate_frames" ? faults::ReplyRule::Kind::Duplicate
                                          : faults::ReplyRule::Kind::Replay;
    rule.delay = std::chrono::microseconds(param(request, "us", 0));
    rule.left = static_cast<std::uint64_t>(param(request, "count", k == "delay_frames" ? 0 : 1));
    rule.until_cleared = rule.left == 0;
    rec.where = Impl::Where::Reply;
    im.replies.add(rule);
    ++frame_faults_;
  } else if (const auto mailbox = faults::mailbox_fault(k)) {
    rec.where = Impl::Where::Mailbox;
    rec.mailbox = *mailbox;
    if (!od::runs_firmware(chain_[rec.slave].device())) {
      return fail(fmt::format("{}: slave {} has no firmware (an ESC without PDI): no mailbox", k, rec.slave));
    }
    for (const auto& [other, r] : im.records) {
      if (r.where == Impl::Where::Mailbox && r.slave == rec.slave && r.mailbox == rec.mailbox) {
        return fail(fmt::format("{}: already engaged as fault {}", k, other));
      }
    }
    if (auto ok = faults::engage(*mailbox, k, chain_[rec.slave].firmware().coe(), request.params); !ok) {
      return fail(ok.error());
    }
  } else if (k == "drive_fault") {
    if (auto ok = in_range(k, request, "code", 1, 0xFFFF); !ok) return fail(ok.error());
    if (auto ok = in_range(k, request, "error_register", 0, 0xFF); !ok) return fail(ok.error());
    if (auto ok = in_range(k, request, "axis", 0, 0xFF); !ok) return fail(ok.error());
    const auto axis = static_cast<std::size_t>(param(request, "axis", 0));
    auto drive = drive_of(k, rec.slave, axis);
    if (!drive) return fail(drive.error());
    rec.drive = *drive;
    rec.where = Impl::Where::Drive;
    rec.port = static_cast<unsigned>(axis);
    if (auto other = same_place(rec.where)) {
      return fail(fmt::format("{}: that drive already has fault {} engaged", k, *other));
    }
    const auto code = static_cast<std::uint16_t>(param(request, "code", 0));
    const auto reg =
        static_cast<std::uint8_t>(param(request, "error_register", ds402::error_register_for(code)));
    rec.drive->set_external_fault(ds402::FaultCode{code, reg});
  } else if (const auto dc = faults::dc_fault(k)) {
    rec.where = Impl::Where::Dc;
    rec.dc = *dc;
    const Nanoseconds now = std::max(chain_.time_seen(), Nanoseconds{0});
    auto ok = faults::engage(*dc, k, rec.slave, chain_[rec.slave].esc(), now, request.params);
    if (!ok) return fail(ok.error());
    rec.dc_state = *ok;
  } else if (const auto input = faults::drive_input(k)) {
    if (auto ok = in_range(k, request, "axis", 0, 0xFF); !ok) return fail(ok.error());
    const auto axis = static_cast<std::size_t>(param(request, "axis", 0));
    auto drive = drive_of(k, rec.slave, axis);
    if (!drive) return fail(drive.error());
    rec.drive = *drive;
    rec.where = Impl::Where::DriveInput;
    rec.port = static_cast<unsigned>(axis);
    auto ok = faults::engage(*input, k, *rec.drive, request.params);
    if (!ok) return fail(ok.error());
    rec.input = *ok;
  }
  ++im.next;
  const EngagedFault& f = im.records.emplace(id, std::move(rec)).first->second.fault;
  if (observer_) observer_(f, true);
  return id;
}

Expected<void, std::string> FaultCatalogue::clear(FaultId id) {
  Impl& im = *impl_;
  const auto it = im.records.find(id);
  if (it == im.records.end()) return fail(fmt::format("no engaged fault {}", id));
  Impl::Record rec = std::move(it->second);
  im.records.erase(it);
  switch (rec.where) {
    case Impl::Where::Link:
      (void)chain_.segment().set_link(rec.slave, rec.port, true);
      break;
    case Impl::Where::Corrupt:
      (void)chain_.segment().corrupt_link(rec.slave, rec.port, 0);
      --frame_faults_;
      break;
    case Impl::Where::Frame:
      (void)im.frames.remove(id);
      --frame_faults_;
      break;
    case Impl::Where::Esm:
      (void)im.guards[rec.slave]->remove(id);
      break;
    case Impl::Where::Drive:
      rec.drive->set_external_fault(std::nullopt);
      break;
    case Impl::Where::SiiChecksum:
      (void)chain_[rec.slave].esc().patch_eeprom_and_reload(esc::kSiiConfigAreaBytes, rec.saved_byte);
      break;
    case Impl::Where::SiiBusy:
      chain_[rec.slave].esc().set_sii_stuck(false, std::max(chain_.time_seen(), Nanoseconds{0}));
      if (chain_.time_seen() != Nanoseconds::min()) (void)chain_.poll(chain_.time_seen());  // the command completes
      break;
    case Impl::Where::Unplug:
      for (unsigned p : rec.ports_cut) (void)chain_.segment().set_link(rec.slave, p, true);
      break;
    case Impl::Where::Reply:
      (void)im.replies.remove(id);  // frames already held still go out
      --frame_faults_;
      break;
    case Impl::Where::Mailbox:
      faults::clear(rec.mailbox, chain_[rec.slave].firmware().coe());
      break;
    case Impl::Where::Power: {
      // The old firmware (and the guard's ESM) is gone: the guard goes with it.
      if (rec.slave < im.guards.size()) im.guards[rec.slave].reset();
      VirtualSlave& s = chain_[rec.slave];
      if (auto on = s.power_on(); !on) return fail(fmt::format("power_cycle: slave {}: {}", rec.slave, on.error()));
      for (unsigned p : rec.ports_cut) (void)chain_.segment().set_link(rec.slave, p, true);
      if (chain_.time_seen() != Nanoseconds::min()) (void)chain_.poll(chain_.time_seen());
      break;
    }
    case Impl::Where::Dc:
      faults::clear(rec.dc, rec.dc_state, chain_[rec.slave].esc(), std::max(chain_.time_seen(), Nanoseconds{0}));
      break;
    case Impl::Where::DriveInput:
      faults::clear(rec.input, *rec.drive);
      break;
  }
  if (observer_) observer_(rec.fault, false);
  return {};
}

void FaultCatalogue::clear_all() {
  while (!impl_->records.empty()) (void)clear(impl_->records.begin()->first);
}

esc::Delivery FaultCatalogue::pass_faulty(std::span<std::uint8_t> frame, Nanoseconds now,
                                          unsigned master_port) noexcept {
  Impl& im = *impl_;
  esc::Delivery d;
  if (!im.frames.empty() && im.frames.lose_before(frame)) {
    d.outcome = esc::Delivery::Outcome::Lost;
  } else {
    d = chain_.pass_frame_on(frame, now, master_port);
    if (d.returned() && !im.frames.empty() && im.frames.lose_after(frame)) d.outcome = esc::Delivery::Outcome::Lost;
    // Held for later or replaced: not sent now (take_reply hands it out).
    if (d.returned() && !im.replies.empty() && im.replies.after_return(frame, d.master_port, now)) {
      d.outcome = esc::Delivery::Outcome::Lost;
    }
  }
  // Faults that ran their course clear themselves (the observer hears it).
  // The lists are reserved at engage time: nothing here allocates.
  // clear() does not touch the spent list, but an observer may engage a
  // fault (the list may then move): re-read it each time.
  for (std::size_t i = 0; i < im.frames.spent().size(); ++i) {
    try {
      (void)clear(im.frames.spent()[i]);
    } catch (...) {  // an observer that throws: the fault is cleared all the same
    }
  }
  im.frames.clear_spent();
  for (std::size_t i = 0; i < im.replies.spent().size(); ++i) {
    try {
      (void)clear(im.replies.spent()[i]);
    } catch (...) {  // an observer that throws: the fault is cleared all the same
    }
  }
  im.replies.clear_spent();
  std::array<FaultId, 16> spent{};  // more cables spent in one frame: found on the next
  std::size_t n = 0;
  for (const auto& [id, r] : im.records) {
    if (r.where == Impl::Where::Corrupt && n < spent.size() &&
        chain_.segment().corruption_pending(r.slave, r.port) == 0) {
      spent[n++] = id;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    try {
      (void)clear(spent[i]);
    } catch (...) {  // an observer that throws: the fault is cleared all the same
    }
  }
  return d;
}

std::optional<FaultCatalogue::HeldReply> FaultCatalogue::take_reply(Nanoseconds now,
                                                                    std::span<std::uint8_t> out) noexcept {
  const auto due = impl_->replies.take_due(now, out);
  if (!due) return std::nullopt;
  return HeldReply{due->length, due->master_port};
}

std::optional<Nanoseconds> FaultCatalogue::next_reply_due() const noexcept { return impl_->replies.next_due(); }

}  // namespace ecat::slave
