// ESCs wired into a network in one process, as real slaves are: a line
// (each slave's port 1 to the next slave's port 0, the master on the first
// slave's port 0), or any tree of 4-port ESCs (couplers, junctions), or a
// ring whose far end comes back to a second master port (cable redundancy).
// Unconnected ports are closed (looped back) as an ET1100 in Auto loop mode
// (Section I §3.4). A frame is carried in place, port by port, in the order
// of the silicon (Section I §3.2 Table 9: 0 -> processing unit -> 3 -> 1 ->
// 2 -> 0; a frame entering at port 1, 2 or 3 is forwarded without processing
// until a closed port 0 turns it into the processing unit), as the wire would
// (ETG.1000.4 §5; shared/spec/esc-registers.md §1.4). docs/esc.md "Ports and
// topology" lists the behaviour and its sources.
//
// Speed: the frame is parsed once (no heap); every slave then walks the
// datagrams in place, so a slave's cost follows the datagrams and the bytes
// it maps, not the frame length. A segment built only with add(Esc&) is a
// line and takes a loop of its own (no port walk); the time is read once.
#pragma once

#include <array>
#include <cstring>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "common/cache_line.hpp"
#include "common/clock.hpp"
#include "common/frame_parser.hpp"
#include "esc/esc.hpp"
#include "esc/pass_hook.hpp"
#include "esc/skip_index.hpp"

namespace ecat::esc {

inline constexpr unsigned kUpstreamPort = 0;
inline constexpr unsigned kDownstreamPort = 1;
// The master's ports: 0 the main one, 1 the redundant one (the ring's far end).
inline constexpr unsigned kMasterPorts = 2;

namespace segment_detail {
// Section I §3.2 Table 9, 4 ports: 0 -> processing unit -> 3 -> 1 -> 2 -> 0.
// kNextPort[p]: the port a frame goes to after port p (after the processing
// unit for p = 0). Ports that do not exist are closed: the frame passes on.
inline constexpr std::array<std::uint8_t, kMaxPorts> kNextPort{3, 2, 0, 1};
}  // namespace segment_detail

// Where a frame sent with Segment::send went.
struct Delivery {
  enum class Outcome : std::uint8_t {
    Returned,   // came back to the master on `master_port`
    Lost,       // sent out of an open port without a link, or into a closed one
    Destroyed,  // circulating frame (Section I §3.5.1), or no way through
    Malformed,  // rejected before any ESC (Segment::last_error says why)
    Corrupted,  // came back to the master on `master_port` with a bad FCS: a cable
                // corrupted it (Segment::corrupt_link); the master drops it as lost
  };
  // 16 bytes, returned in two registers: a 24-byte Delivery was built on the
  // stack field by field and read back as one 16-byte load, which cannot be
  // forwarded from the smaller stores and stalled every frame (issue 30:
  // the one-slave FPRD 3x its 49fab26 time with 1.33x its instructions).
  Nanoseconds at{0};                 // when it reached the master port (when Returned)
  unsigned processed = 0;            // processing units the frame passed
  std::uint8_t master_port = 0;      // valid when Returned (< kMasterPorts)
  Outcome outcome = Outcome::Lost;
  bool returned() const noexcept { return outcome == Outcome::Returned; }
};
static_assert(sizeof(Delivery) == 16, "Delivery is returned in two registers");

class Segment {
 public:
  // Wire-plus-forwarding delay of a link from one slave's port to the
  // neighbour's, used for the port arrival times handed to each DC unit.
  static constexpr Nanoseconds kDefaultHopDelay{1000};
  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);

  Segment() = default;
  explicit Segment(Nanoseconds hop_delay) : hop_delay_(hop_delay), out_step_(hop_delay), back_step_(hop_delay) {}
  // The Escs point at the segment (esc/pass_hook.hpp): it stays where it is.
  Segment(const Segment&) = delete;
  Segment& operator=(const Segment&) = delete;
  ~Segment();

  // --- Set-up (the Escs must outlive the Segment) ---
  // Appends `esc` at the end of the line: its port 0 to the previous slave's
  // port 1 (the master's port 0 for the first). Returns its index.
  std::size_t add(Esc& esc);
  // Adds `esc` with its port `port` cabled to port `parent_port` of slave
  // `parent` (an index returned earlier), with that link's delay (default:
  // the segment's hop delay). Returns its index.
  std::size_t add(Esc& esc, std::size_t parent, unsigned parent_port, unsigned port = kUpstreamPort,
                  std::optional<Nanoseconds> delay = std::nullopt);
  // Cables port `port` of slave `slave` to the master's port `master_port`
  // (1: the redundant port closing a ring; 0 is where add() puts the first slave).
  void connect_master(unsigned master_port, std::size_t slave, unsigned port,
                      std::optional<Nanoseconds> delay = std::nullopt);

  // --- Run time ---
  // Cuts (up = false) or restores the cable on port `port` of slave `slave`:
  // both ends lose or regain their link (a master port end has no ESC), and
  // each ESC reacts as silicon does (Esc::set_link: DL status, loop closed in
  // Auto, lost-link counter). Returns false if nothing is cabled there.
  bool set_link(std::size_t slave, unsigned port, bool up) noexcept;
  // Whether the cable on that port is connected and up.
  bool link_up(std::size_t slave, unsigned port) const noexcept;
  // The slave and port cabled to `port` of `slave`, or {kNone, master port} for the master.
  struct Peer {
    std::size_t slave = kNone;
    unsigned port = 0;
    bool master = false;
  };
  std::optional<Peer> peer(std::size_t slave, unsigned port) const noexcept;
  // Fault injection (Section I §14, error counters): the cable on port
  // `port` of slave `slave` corrupts the next `frames` frames that cross it,
  // in either direction (a frame crossing it twice is hit once). The ESC
  // that receives a corrupted frame counts it as its own error at that port
  // (0x0300+2n; with RxError also 0x0301+2n) and marks it; every later port
  // the frame enters counts a forwarded error (0x0308+n), every processing
  // unit it passes 0x030C and discards its datagrams; the master gets it
  // with a bad FCS (Delivery::Outcome::Corrupted). 0 frames repairs the
  // cable. Returns false if nothing is cabled there.
  enum class CableFault : std::uint8_t {
    Crc,      // bits flipped on the wire: a bad FCS at the receiving port
    RxError,  // a symbol error the PHY reports (RX_ER / EBUS Manchester violation)
  };
  bool corrupt_link(std::size_t slave, unsigned port, unsigned frames, CableFault fault = CableFault::Crc) noexcept;
  // Frames the cable on that port will still corrupt.
  unsigned corruption_pending(std::size_t slave, unsigned port) const noexcept;

  // True while the segment is a line built by add(Esc&) alone whose ESCs
  // all take the same time inside (EscConfig::processing_delay and
  // forwarding_delay equal: a line of one ESC type).
  bool is_line() const noexcept { return line_; }

  std::size_t size() const noexcept { return escs_.size(); }
  Esc& operator[](std::size_t i) noexcept { return *escs_[i]; }

  // Carries `frame` (a whole Ethernet frame) sent by the master on port 0
  // at time `now`: every reached ESC processes it in the silicon's order,
  // then the source MAC gets the "processed" bit. Returns true when the
  // frame comes back to the master (on either port). Returns false, and
  // leaves every ESC unchanged except its error counters, if the frame is
  // malformed; false also when it is lost (destroyed as circulating, or
  // sent out of an open port with no link). Non-EtherCAT frames return
  // false and count nothing.
  bool process_frame(std::span<std::uint8_t> frame, Nanoseconds now) noexcept {
    return send(frame, now, 0).returned();
  }
  // The same, sent on master port `master_port`; says where it came back.
  // One ESC on a line (the virtual slave of most runs) takes send_one, with
  // its pass compiled in; every other segment send_many (issue 30: the call
  // into a one-ESC body cost that frame ~20 instructions, its pass inline in
  // the shared body cost every other frame 15).
  Delivery send(std::span<std::uint8_t> frame, Nanoseconds now, unsigned master_port = 0) noexcept {
    if (master_port == 0 && path_ == LinePath::OneEsc) [[likely]] return send_one(frame, now);
    return send_many(frame, now, master_port);
  }

  // Runs every ESC's timers; returns the earliest next deadline.
  std::optional<Nanoseconds> poll(Nanoseconds now) noexcept;

  // Skipping (issue 16 item 5, docs/esc.md): on a line, a frame enters only
  // the ESCs it addresses or that are not passive; the others take in its
  // times when next looked at. Off: every frame enters every ESC it
  // reaches (the reference the tests compare with). On by default.
  void set_skipping(bool on) noexcept { skipping_ = on; }
  bool skipping() const noexcept { return skipping_; }
  // The ESCs whose processing unit a frame entered (or that anything else
  // may have changed) since the caller last cleared the bits: bit i of word
  // i / 64 is ESC i. slave::Chain asks only those slaves' firmware.
  std::span<std::uint64_t> entered() noexcept { return index_.entered_words(); }
  // The ESCs accessed from outside a frame (PDI, poll, link, reset:
  // Esc::touch) since the segment last read them again - at its next frame
  // that skips, or never on a dense line (bit i of word i / 64: ESC i).
  // slave::Chain looks at these slaves' timers again before it polls.
  std::span<const std::uint64_t> dirty() noexcept { return index_.dirty_words(); }

  std::uint64_t frames_processed() const noexcept { return processed_; }
  std::uint64_t frames_dropped() const noexcept { return dropped_; }
  FrameError last_error() const noexcept { return last_error_; }

 private:
  // One end of a cable: the slave (or master port) at the other end.
  struct Link {
    std::uint32_t slave = kNoSlave;  // kMasterSlave: a master port
    std::uint8_t port = 0;
    bool up = false;
    Nanoseconds delay{0};
  };
  static constexpr std::uint32_t kNoSlave = 0xFFFFFFFFu;
  static constexpr std::uint32_t kMasterSlave = 0xFFFFFFFEu;

  std::size_t append(Esc& esc);
  void cable(std::size_t a, unsigned pa, std::size_t b, unsigned pb, Nanoseconds delay);
  // send's two bodies. Each, and the frame's way along a line after them
  // (carry_line, carry_dense_line), starts on a cache line: code added
  // anywhere before them in the library otherwise moves their loops against
  // the fetch blocks (a change elsewhere in esc/ made the FPRD through 100
  // ESCs 1.06-1.08x slower with the same instructions; docs/performance-log.md
  // "Session 32").
  [[gnu::noinline, gnu::aligned(kCacheLineBytes)]] Delivery send_one(std::span<std::uint8_t> frame,
                                                                     Nanoseconds now) noexcept;
  [[gnu::noinline, gnu::aligned(kCacheLineBytes)]] Delivery send_many(std::span<std::uint8_t> frame, Nanoseconds now,
                                                                      unsigned master_port) noexcept;
  // The frame checked as a whole before any ESC acts (both bodies).
  [[gnu::always_inline]] inline ValidatedDatagrams validated(std::span<std::uint8_t> frame) noexcept;
  // What both bodies do with the frame once it is through (the counters, SOURCE_MAC[1]).
  [[gnu::always_inline]] inline Delivery delivered(Delivery d, std::span<std::uint8_t> frame) noexcept;
  // A line frame that skips (one that enters every ESC takes carry_dense:
  // enters_every).
  [[gnu::aligned(kCacheLineBytes)]] Delivery carry_line(DatagramView first, std::size_t count,
                                                       Nanoseconds now) noexcept;
  // The line without skipping: every ESC entered until the frame turns back
  // (inline in send_many).
  [[gnu::always_inline]] inline Delivery carry_dense(DatagramView first, std::size_t count, Nanoseconds now) noexcept;
  // Its body for longer lines, out of line; the one-ESC body inline in
  // send_one (inline in send it made the one-drive cycle 1.07x slower by the
  // code's layout: docs/performance-log.md "Session 23").
  [[gnu::noinline, gnu::aligned(kCacheLineBytes)]] Delivery carry_dense_line(DatagramView first, std::size_t count,
                                                                          Nanoseconds now) noexcept;
  [[gnu::always_inline]] inline Delivery carry_one(DatagramView first, std::size_t count, Nanoseconds now) noexcept;
  // Out of send's hot path: a malformed frame, and the port walks.
  [[gnu::noinline]] Delivery reject(FrameError error, Nanoseconds now, unsigned master_port) noexcept;
  [[gnu::noinline]] Delivery carry_walk(DatagramView first, std::size_t count, Nanoseconds now,
                                        unsigned master_port) noexcept;
  // The port walk proper (carry_walk takes trees and rings with skipping
  // on to carry_route instead).
  Delivery carry_every(DatagramView first, std::size_t count, Nanoseconds now, unsigned master_port) noexcept;
  // Lines shorter than this take carry_dense: planning a frame (SkipIndex)
  // costs about as much as entering three or four passive ESCs, and the
  // index kept up to date after every entered ESC more (issue 30: the
  // one-slave FPRD cost 205 instructions at 49fab26, 610 with the index).
  static constexpr std::size_t kSkipFrom = 4;
  // A logical datagram over the process data of at least 1 / kDenseShare of
  // the ESCs takes carry_dense (Segment::maps_most).
  static constexpr std::size_t kDenseShare = 2;
  // How many ESCs ahead of the pass carry_line asks for an ESC's object
  // lines, and for the lines its pointers lead to (Esc::prefetch_pass_object):
  // a mapped ESC's pass is some 20-40 ns, an L3 hit about as long; measured
  // at 1000 drives (docs/performance-log.md "Session 22").
  static constexpr std::size_t kPrefetchObjectAhead = 4;
  static constexpr std::size_t kPrefetchTargetsAhead = 2;
  Delivery carry_ports(DatagramView first, std::size_t count, Nanoseconds now, unsigned master_port) noexcept;
  // carry_ports from the frame's arrival at port `p` of slave `n` at time
  // `t`, the walk's step `step`; with `resume`, its processing unit has
  // already had the frame, `*resume` the time inside so far
  // (carry_route hands a frame over to it there).
  Delivery walk_ports(Delivery d, DatagramView first, std::size_t count, std::size_t n, unsigned p, Nanoseconds t,
                      std::size_t step, const Nanoseconds* resume) noexcept;
  // Trees and rings with skipping on (issue 30 item 2, esc/segment_route.cpp):
  // the frame takes the route the port walk would, worked out once for the
  // ports' states (build_route), and enters only the ESCs it addresses or
  // maps and the ones not passive; the others take in its times later
  // (RoutePass). Hands over to the port walk when an entered ESC's ports
  // change under the frame.
  [[gnu::noinline]] Delivery carry_route(DatagramView first, std::size_t count, Nanoseconds now,
                                         unsigned master_port) noexcept;
  struct Route;
  template <bool all>
  Delivery carry_route_as(DatagramView first, std::size_t count, Nanoseconds now, unsigned master_port) noexcept;
  void build_route(unsigned master_port);
  void plan_route(const Route& r, DatagramView first, std::size_t count, Nanoseconds now) noexcept;
  // The frame leaves the route after the event `at` of its route: the
  // events before it are done in full, as the port walk does them.
  void materialize(const Route& r, std::size_t at, Nanoseconds now) noexcept;
  void note_entered_route(std::size_t i) noexcept;
  void record_route_pass(unsigned master_port, Nanoseconds start) noexcept;
  // The ESC's open ports as one word (the 4 flags' bytes: compared only
  // with another port_mask), inline: note_entered<true> takes it for every
  // entered or accessed ESC of a tree or ring.
  static std::uint32_t port_mask(const Esc& e) noexcept {
    static_assert(sizeof(e.port_open_) == sizeof(std::uint32_t));
    std::uint32_t m;
    std::memcpy(&m, e.port_open_.data(), sizeof m);
    return m;
  }
  // Dirty ESCs whose ports opened or closed since the route was built.
  void check_dirty_ports() noexcept;
  // The port walk of carry_ports for frames that are or may become broken
  // (a cable with a fault, or a frame the processing unit rejects:
  // `parsed` false), with the error counting of Section I §14
  // (esc/segment_faults.cpp; kept apart so the hot walks stay as they are).
  Delivery carry_faulty(DatagramView first, std::size_t count, Nanoseconds now, unsigned master_port,
                        bool parsed) noexcept;
  // A cable with a fault: one end (a slave's port; for a master cable the
  // slave end), frames left, and the frame it last hit.
  struct CableFaultState {
    std::uint32_t slave = kNoSlave;
    std::uint8_t port = 0;
    CableFault fault = CableFault::Crc;
    unsigned left = 0;
    std::uint64_t hit_frame = 0;
  };
  CableFaultState* fault_on(std::size_t slave, unsigned port) noexcept;
  // Whether a frame addresses every ESC (a broadcast, xRMW, or more APxx
  // than kMaxAutoIncrement): it enters all of them, unplanned.
  static bool enters_all(DatagramView first, std::size_t count) noexcept;
  // Whether a logical datagram of the frame spans the process data of every
  // ESC as the index last read them (SkipIndex::maps_every_esc), or of at
  // least 1 / kDenseShare of them (SkipIndex::spans_starting_in): skipping
  // would pass few by. A guess that only chooses the path: both are exact.
  bool maps_most(DatagramView first, std::size_t count) noexcept;
  // Either: the frame enters every ESC of a line and skips none.
  [[gnu::noinline]] bool enters_every(DatagramView first, std::size_t count) noexcept;
  // Marks the ESCs a frame that does not enter all must enter (SkipIndex).
  void plan(DatagramView first, std::size_t count, Nanoseconds now) noexcept;
  // The planning walk of plan and plan_route (esc/segment_marking.hpp): the
  // ESCs a frame's datagrams address are marked in the SkipIndex; the
  // ADP-th of `positions` on the frame's way is ESC esc_at(ADP).
  template <class EscAt>
  [[gnu::always_inline]] inline void mark_addressed(DatagramView first, std::size_t count, std::size_t positions, EscAt esc_at) noexcept;
  // What the index keeps of ESC i, read after a frame entered it.
  // kRoute: a tree or ring, where a passive ESC may send the frame on out
  // of any port (the route knows where) and a change of its ports makes
  // the routes stale.
  template <bool kRoute = false>
  [[gnu::always_inline]] inline void note_entered(std::size_t i) noexcept;
  static std::size_t logical_spans(const Esc& e, SkipIndex::Spans& out) noexcept;
  template <bool kRoute = false>
  void refresh_dirty() noexcept;
  // The frame just carried becomes the line's latest (LinePass).
  void record_pass(Nanoseconds start, std::uint32_t reached, bool returned) noexcept;
  void hook(std::size_t i) noexcept;

  std::vector<Esc*> escs_;
  // Per slave: its EscConfig processing delay and forwarding delay per
  // receiving port (port_forwarding_delay where set, else forwarding_delay;
  // the port walks add them; a line whose ESCs differ in them takes the
  // port walk).
  struct InnerDelay {
    Nanoseconds processing{0};
    std::array<Nanoseconds, kMaxPorts> forwarding{};  // [0] unused
  };
  std::vector<InnerDelay> inner_;
  std::vector<std::array<Link, kMaxPorts>> links_;
  // Per slave: the frame number at which it was last touched / processed
  // (early receive times before the processing unit, carry_ports).
  std::vector<std::uint64_t> touched_;
  std::array<Link, kMasterPorts> master_{};
  std::vector<CableFaultState> faults_;  // empty on a healthy segment
  std::uint64_t frame_number_ = 0;
  Nanoseconds hop_delay_ = kDefaultHopDelay;
  // The line path's steps (LinePass::out/back): the cable plus the first
  // ESC's processing delay out, plus its forwarding delay back.
  Nanoseconds out_step_ = kDefaultHopDelay;
  Nanoseconds back_step_ = kDefaultHopDelay;
  // Skipping (line path only).
  static constexpr std::size_t kMaxAutoIncrement = 32;
  struct AutoIncrement {
    DatagramView datagram;
    std::uint16_t adp = 0;  // as the frame arrived
  };
  std::array<AutoIncrement, kMaxAutoIncrement> auto_increment_{};
  std::size_t auto_increments_ = 0;
  SkipIndex index_;
  LinePass pass_;
  std::vector<std::uint32_t> visited_;  // the ESCs one frame entered, in order
  // Set by carry_dense, which keeps no index: the next skipping frame
  // enters every ESC to read them all again.
  bool index_stale_ = false;
  // Which of send's paths a frame from master port 0 takes, kept by
  // refresh_path at every change of what decides it (ESCs added, cables,
  // links, cable faults), so that send tests one byte per frame.
  enum class LinePath : std::uint8_t {
    OneEsc,  // one ESC on a line, its master cable up, no fault: carry_one
    Line,    // a line with no cable fault: carry_dense or carry_line
    Walk,    // a tree, a ring or a fault: carry_walk
  };
  LinePath path_ = LinePath::Line;  // no ESC yet: carry_dense loses the frame
  void refresh_path() noexcept {
    if (!faults_.empty() || !line_) {
      path_ = LinePath::Walk;
    } else {
      path_ = escs_.size() == 1 && master_[0].up && master_[0].slave == 0 ? LinePath::OneEsc : LinePath::Line;
    }
  }
  // Set by record_pass: ESCs the skipping path passed by may not have taken
  // in pass_ yet (Esc::sync_pass); carry_dense syncs them all once first.
  bool passes_pending_ = false;
  // What note_entered keeps of each ESC's addressing, read again only when
  // the ESC's address epoch moved (issue 30 item 1: at 1000 drives the
  // registers' lines - 0x0010, 0x0100, 0x0200 - and the ESC's config were
  // last-level misses at every entered or accessed ESC), and the FMMU epoch
  // of its spans: one small record per ESC, four to a cache line.
  struct EscView {
    std::uint32_t address_epoch = 0;  // Esc::address_epoch_ when read
    std::uint32_t fmmu_epoch = 0;     // Esc::fmmu_epoch_ when its spans were last read
    std::uint32_t address = 0;        // station | alias << 16 (alias = station while not enabled)
    std::uint16_t event_mask = 0;     // ECAT event mask 0x0200
    bool open = false;                // fast paths on, port 0 open, no ESC reset requested
    bool down = false;                // and the line's frame goes on out of port 1 (Esc::line_route_)
  };
  std::vector<EscView> views_;
  [[gnu::noinline]] void read_addressing(std::size_t i) noexcept;
  // Trees and rings (carry_route): the port walk of each master port's
  // frames, for the ports' states when it was built.
  struct RouteEvent {
    enum class Kind : std::uint8_t { Arrive, Unit };
    std::uint32_t slave = 0;
    std::uint8_t port = 0;     // where the frame came in
    Kind kind = Kind::Arrive;
    bool after_unit = false;   // Arrive: the slave's processing unit already had the frame
    std::uint32_t step = 0;    // the walk's step (arrivals at a slave before this one)
    Nanoseconds t{0};          // Arrive: the arrival; Unit: processing (from the send)
    Nanoseconds arrived{0};    // Unit: the arrival at `port`
  };
  struct Route {
    bool built = false;
    bool usable = false;             // false: a unit twice, or circling: the port walk takes it
    std::uint64_t epoch = 0;         // topology_epoch_ when built
    Delivery::Outcome outcome = Delivery::Outcome::Lost;
    unsigned out_port = 0;           // Returned: the master port
    Nanoseconds out_at{0};           // Returned: when (from the send)
    std::uint32_t closed_slave = kNoSlave;  // Lost at a closed port: whose
    std::uint8_t closed_port = 0;
    std::vector<RouteEvent> events;
    std::vector<std::uint32_t> units;       // the slave of each processing unit, in order
    std::vector<std::uint32_t> unit_event;  // its event
    std::vector<std::uint32_t> ordinal;     // per slave: its unit's place in `units`, or kNoSlave
    std::vector<Nanoseconds> unit_at;       // per slave: RoutePass::unit_at
    std::vector<Nanoseconds> seen_at;       // per slave: RoutePass::seen_at
    std::vector<std::uint32_t> begin;       // per slave + 1: where its events start in by_slave
    std::vector<std::uint32_t> by_slave;    // event numbers by slave, in order
    Nanoseconds last_unit{0};
  };
  std::array<Route, kMasterPorts> routes_{};
  std::array<RoutePass, kMasterPorts> route_passes_{};
  std::vector<std::uint32_t> port_masks_;  // per slave: its open ports when the routes were built
  std::uint64_t topology_epoch_ = 1;       // +1 when a port opened or closed or a cable went up or down
  std::vector<std::uint64_t> unit_visit_;  // one frame: bit k = the k-th unit is entered
  bool skipping_ = true;
  bool line_ = true;
  std::uint64_t processed_ = 0;
  std::uint64_t dropped_ = 0;
  FrameError last_error_ = FrameError::TooShort;
};

}  // namespace ecat::esc
