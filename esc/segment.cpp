// Frame transport through ESCs wired as a line, a tree or a ring
// (Section I §3.2 frame processing order, §3.4 loop control).
#include "esc/segment.hpp"

#include "esc/datagram_engine.hpp"
#include "esc/segment_marking.hpp"

#include <algorithm>
#include <bit>

namespace ecat::esc {

using segment_detail::kNextPort;

std::size_t Segment::append(Esc& esc) {
  escs_.push_back(&esc);
  InnerDelay inner{esc.config().processing_delay, {}};
  for (unsigned p = 1; p < kMaxPorts; ++p) {
    inner.forwarding[p] = esc.config().port_forwarding_delay[p].value_or(esc.config().forwarding_delay);
  }
  inner_.push_back(inner);
  // The line path takes one time inside for every ESC (a line of one type;
  // a frame on a line returns through port 1, so forwarding[1] is its back
  // step); ESCs that differ take the port walk, which adds each one's own.
  if (inner_.size() == 1) {
    out_step_ = hop_delay_ + inner.processing;
    back_step_ = hop_delay_ + inner.forwarding[kDownstreamPort];
  } else if (inner.processing != inner_.front().processing || inner.forwarding != inner_.front().forwarding) {
    line_ = false;
  }
  links_.emplace_back();
  touched_.push_back(0);
  touched_.push_back(0);  // two words per slave: touched, processed
  visited_.push_back(0);
  EscView view;
  view.address_epoch = esc.address_epoch_ - 1;  // not read yet
  view.fmmu_epoch = esc.fmmu_epoch_ - 1;
  views_.push_back(view);
  port_masks_.push_back(0);
  ++topology_epoch_;
  refresh_path();
  const std::size_t i = escs_.size() - 1;
  if (index_.resize(escs_.size())) {
    for (std::size_t k = 0; k < i; ++k) hook(k);
  }
  hook(i);
  return i;
}

// The ESC takes in this segment's line frames and marks itself for a full
// pass when accessed from outside a frame (esc/pass_hook.hpp).
void Segment::hook(std::size_t i) noexcept {
  PassHook& h = escs_[i]->hook_;
  escs_[i]->sync_pass();  // anything of an earlier segment first
  h.line = &pass_;
  h.dirty_word = index_.dirty_word(i);
  h.dirty_bit = SkipIndex::bit(i);
  h.index = static_cast<std::uint32_t>(i);
  h.synced = pass_.frame;
}

Segment::~Segment() {
  for (Esc* e : escs_) {
    e->sync_pass();
    e->hook_ = PassHook{};
  }
}

void Segment::cable(std::size_t a, unsigned pa, std::size_t b, unsigned pb, Nanoseconds delay) {
  links_[a][pa] = Link{static_cast<std::uint32_t>(b), static_cast<std::uint8_t>(pb), true, delay};
  links_[b][pb] = Link{static_cast<std::uint32_t>(a), static_cast<std::uint8_t>(pa), true, delay};
  ++topology_epoch_;
  escs_[a]->set_link(pa, true);
  escs_[b]->set_link(pb, true);
  refresh_path();
}

std::size_t Segment::add(Esc& esc) {
  const std::size_t i = append(esc);
  if (i == 0) {
    connect_master(0, 0, kUpstreamPort, Nanoseconds{0});
  } else {
    cable(i - 1, kDownstreamPort, i, kUpstreamPort, hop_delay_);
  }
  return i;
}

std::size_t Segment::add(Esc& esc, std::size_t parent, unsigned parent_port, unsigned port,
                         std::optional<Nanoseconds> delay) {
  if (escs_.empty() || parent >= escs_.size() || parent_port >= kMaxPorts || port >= kMaxPorts) return kNone;
  if (parent != escs_.size() - 1 || parent_port != kDownstreamPort || port != kUpstreamPort || delay) line_ = false;
  const std::size_t i = append(esc);
  cable(parent, parent_port, i, port, delay.value_or(hop_delay_));
  return i;
}

void Segment::connect_master(unsigned master_port, std::size_t slave, unsigned port, std::optional<Nanoseconds> delay) {
  if (master_port >= kMasterPorts || slave >= escs_.size() || port >= kMaxPorts) return;
  if (master_port != 0 || slave != 0 || port != kUpstreamPort) line_ = false;
  const Nanoseconds d = delay.value_or(Nanoseconds{0});
  master_[master_port] = Link{static_cast<std::uint32_t>(slave), static_cast<std::uint8_t>(port), true, d};
  links_[slave][port] = Link{kMasterSlave, static_cast<std::uint8_t>(master_port), true, d};
  ++topology_epoch_;
  escs_[slave]->set_link(port, true);
  refresh_path();
}

bool Segment::set_link(std::size_t slave, unsigned port, bool up) noexcept {
  if (slave >= escs_.size() || port >= kMaxPorts) return false;
  Link& l = links_[slave][port];
  if (l.slave == kNoSlave) return false;
  if (l.up == up) return true;
  l.up = up;
  ++topology_epoch_;  // the routes of trees and rings (carry_route) go another way
  escs_[slave]->set_link(port, up);
  if (l.slave == kMasterSlave) {
    master_[l.port].up = up;
  } else {
    links_[l.slave][l.port].up = up;
    escs_[l.slave]->set_link(l.port, up);
  }
  refresh_path();
  return true;
}

bool Segment::link_up(std::size_t slave, unsigned port) const noexcept {
  return slave < escs_.size() && port < kMaxPorts && links_[slave][port].slave != kNoSlave && links_[slave][port].up;
}

std::optional<Segment::Peer> Segment::peer(std::size_t slave, unsigned port) const noexcept {
  if (slave >= escs_.size() || port >= kMaxPorts) return std::nullopt;
  const Link& l = links_[slave][port];
  if (l.slave == kNoSlave) return std::nullopt;
  if (l.slave == kMasterSlave) return Peer{kNone, l.port, true};
  return Peer{l.slave, l.port, false};
}

// The frame is validated completely before the first ESC acts (a
// malformed frame changes nothing but the error counters); then each ESC's
// pass (esc/datagram_engine.hpp, inline) walks the datagrams in place. The
// short healthy line (carry_dense) and the one ESC (carry_one) are compiled
// into send_many and send_one, the rest are calls (issue 30: each level of
// call on the way cost ~20 instructions of register saves per frame).
ValidatedDatagrams Segment::validated(std::span<std::uint8_t> frame) noexcept {
  const detail::EthercatAt at = detail::find_ethercat(frame);
  ValidatedDatagrams valid;
  if (at.ok) [[likely]] {
    valid = validate_ethercat(frame, at.offset);
  } else {
    valid.error = at.error;
  }
  return valid;
}

Delivery Segment::delivered(Delivery d, std::span<std::uint8_t> frame) noexcept {
  if (!d.returned()) [[unlikely]] {
    ++dropped_;
    return d;
  }
  // Every frame that passed a processing unit leaves with SOURCE_MAC[1] set (Section I §3.2).
  if (d.processed != 0) frame[kMacSize] = static_cast<std::uint8_t>(frame[kMacSize] | kSourceMacProcessedBit);
  ++processed_;
  return d;
}

Delivery Segment::send_one(std::span<std::uint8_t> frame, Nanoseconds now) noexcept {
  const ValidatedDatagrams valid = validated(frame);
  if (valid.count == 0) [[unlikely]] return reject(valid.error, now, 0);
  return delivered(carry_one(DatagramView(valid.first), valid.count, now), frame);
}

Delivery Segment::send_many(std::span<std::uint8_t> frame, Nanoseconds now, unsigned master_port) noexcept {
  const ValidatedDatagrams valid = validated(frame);
  if (valid.count == 0) [[unlikely]] return reject(valid.error, now, master_port);
  const DatagramView first(valid.first);
  Delivery d;
  if (master_port == 0 && path_ == LinePath::Line) [[likely]] {
    d = !skipping_ || escs_.size() < kSkipFrom || enters_every(first, valid.count)
            ? carry_dense(first, valid.count, now)
            : carry_line(first, valid.count, now);
  } else {
    d = carry_walk(first, valid.count, now, master_port);
  }
  return delivered(d, frame);
}

Delivery Segment::reject(FrameError error, Nanoseconds now, unsigned master_port) noexcept {
  last_error_ = error;
  ++dropped_;
  if (error != FrameError::NotEtherCat) {
    // The first processing unit rejects the datagram structure (0x030C) and
    // marks the frame; every later port counts a forwarded error (0x0308+n)
    // and every later unit 0x030C (Section I §14.1 Table 51, §14.2). The
    // port walk enters ESCs without the line's bookkeeping (as below).
    ++topology_epoch_;
    for (Esc* e : escs_) e->sync_pass();
    (void)carry_faulty(DatagramView{}, 0, now, master_port, false);
    index_.must_visit_all();
    index_.entered_all();
  }
  Delivery d;
  d.outcome = Delivery::Outcome::Malformed;
  return d;
}

// The port walks enter ESCs without the line's bookkeeping: each takes in
// the line's last frame first, and all are entered in full afterwards.
Delivery Segment::carry_walk(DatagramView first, std::size_t count, Nanoseconds now, unsigned master_port) noexcept {
  // Trees and rings skip (esc/segment_route.cpp); decided here, not in
  // send_many, whose lines' path stays as it was (issue 30: every
  // instruction there is paid by every frame).
  if (faults_.empty() && skipping_ && !line_) return carry_route(first, count, now, master_port);
  return carry_every(first, count, now, master_port);
}

Delivery Segment::carry_every(DatagramView first, std::size_t count, Nanoseconds now, unsigned master_port) noexcept {
  ++topology_epoch_;  // ports may open or close on the way: the routes of carry_route are built again
  for (Esc* e : escs_) e->sync_pass();
  const Delivery d = !faults_.empty() ? carry_faulty(first, count, now, master_port, true)
                                      : carry_ports(first, count, now, master_port);
  index_.must_visit_all();
  index_.entered_all();
  return d;
}

// A line: each ESC's port 0 faces the master. Ports 2 and 3 have no
// neighbour, so after the processing unit the frame goes on out of port 1,
// back (ports 3, 1, 2 closed) or is lost (Esc::line_route_, kept by
// update_ports); no port walk per ESC.
//
// Skipping (issue 16 item 5): the frame enters only the ESCs plan() marked
// (SkipIndex::next); every ESC between two of them is passive - port 0
// open, the frame going on out of port 1, nothing to OR into the IRQ field,
// no latch armed, no timer due - and the frame's only effect on it, its
// times, it takes in later (Esc::sync_pass). The ADP of an APxx is what it
// would be after the increments of the ESCs before (the arriving ADP + the
// position), set before each ESC entered and after the last. A line shorter
// than kSkipFrom, or with skipping off, takes carry_dense instead.
//
// A frame that enters every ESC - a broadcast (the cycle's first frame), or
// a logical datagram over the process data of every ESC (the one LRW of a
// typical cycle) - takes the dense loop (carry_dense) instead: skipping
// would pass none by, and the index it would keep up to date after each
// ESC (some 90-110 instructions per ESC, issue 30: BRD and LRW through
// 10-100 ESCs 1.3-1.6x their 49fab26 time) is read again anyway once the
// firmware has touched the ESCs. So does a logical datagram that maps at
// least 1 / kDenseShare of the ESCs: the dense loop's quick reject at the
// others costs less than that bookkeeping at the ones entered (an LRW over
// 743 of 1000 ESCs: 236,000 instructions dense, 334,000 skipping). The
// next skipping frame reads every ESC into the index first (index_stale_),
// without entering it.
bool Segment::enters_every(DatagramView first, std::size_t count) noexcept {
  return enters_all(first, count) || maps_most(first, count);
}

Delivery Segment::carry_line(DatagramView first, std::size_t count, Nanoseconds now) noexcept {
  Delivery d;
  if (escs_.empty() || !master_[0].up) [[unlikely]] return d;
  if (index_stale_) [[unlikely]] {
    // Dense frames kept no index: every ESC is read again (as if accessed
    // from outside a frame), not entered.
    index_stale_ = false;
    index_.all_dirty();
  }
  refresh_dirty();
  plan(first, count, now);
  const std::size_t n = escs_.size();
  std::size_t reached = 0;  // ESCs whose processing unit the frame entered
  std::size_t passed = 0;   // ... and left again (the ADP increments)
  std::size_t visited = 0;  // entered ESCs listed in visited_
  bool ended = false;       // lost or destroyed inside the line
  bool back = false;        // turned back by an ESC whose port 1 is closed
  for (std::size_t i = index_.next(0); i < n; i = index_.next(i + 1)) {
    Esc* esc = escs_[i];
    // The lines of the ESCs a few ahead (Esc::prefetch_pass_object): on a
    // mapped run the next ones are entered too; elsewhere a few lines are
    // fetched for nothing.
    if (i + kPrefetchObjectAhead < n) escs_[i + kPrefetchObjectAhead]->prefetch_pass_object();
    if (i + kPrefetchTargetsAhead < n) escs_[i + kPrefetchTargetsAhead]->prefetch_pass_targets();
    esc->sync_pass();
    if (!esc->port_open_[kUpstreamPort]) [[unlikely]] {
      passed = reached = i;
      esc->frame_at_closed_port(kUpstreamPort);  // a closed port takes nothing in
      ended = true;
      break;
    }
    for (std::size_t k = 0; k < auto_increments_; ++k) {
      auto_increment_[k].datagram.set_adp(static_cast<std::uint16_t>(auto_increment_[k].adp + i));
    }
    reached = i + 1;
    index_.entered(i);
    visited_[visited++] = static_cast<std::uint32_t>(i);
    if (!esc->process_datagrams(first, count, now + out_step_ * static_cast<std::int64_t>(i))) [[unlikely]] {
      passed = i;
      d.outcome = Delivery::Outcome::Destroyed;
      note_entered(i);
      ended = true;
      break;
    }
    passed = reached;
    note_entered(i);
    const Esc::LineRoute route = esc->line_route_;
    if (route == Esc::LineRoute::Back) {  // closed: the frame turns back here
      back = true;
      break;
    }
    if (route == Esc::LineRoute::Lost) [[unlikely]] {
      ended = true;
      break;
    }
  }
  if (!ended && !back) reached = passed = n;  // went on out of the last ESC's port 1 (skipped or not)
  for (std::size_t k = 0; k < auto_increments_; ++k) {
    auto_increment_[k].datagram.set_adp(static_cast<std::uint16_t>(auto_increment_[k].adp + passed));
  }
  const bool returned = !ended && d.outcome != Delivery::Outcome::Destroyed;
  record_pass(now, static_cast<std::uint32_t>(reached), returned);
  // The ESCs the frame entered take in its times now, as the dense path
  // does, rather than at their next look (Esc::apply_pass): the frame
  // reached their port 0 when they processed it, and on the way back it
  // passes each earlier one's port 1 - the last reached ESC turns it round
  // (reached steps out, the last one into ESC reached - 2's port 1), then
  // one step back per ESC (LinePass::latest). DcUnit::on_frame_arrival
  // keeps that time (and latches it when a 0x0900 write of this frame armed
  // the receive latch). The ESCs passed by take it from the pass record.
  const auto r = static_cast<std::int64_t>(reached);
  const Nanoseconds turned = now + out_step_ * r;
  for (std::size_t k = 0; k < visited; ++k) {
    const std::size_t i = visited_[k];
    Esc* esc = escs_[i];
    if (esc->hook_.line == &pass_) esc->hook_.synced = pass_.frame;
    if (returned && i + 1 < reached) {
      esc->dc_.on_frame_arrival(static_cast<int>(kDownstreamPort),
                                turned + back_step_ * (r - 2 - static_cast<std::int64_t>(i)));
    }
  }
  if (!returned) return d;
  // ESC 0 sends it to the master after its forwarding delay (the master's cable takes 0).
  d.outcome = Delivery::Outcome::Returned;
  d.master_port = 0;
  d.at = turned + back_step_ * (r - 1) - hop_delay_;
  d.processed = static_cast<unsigned>(reached);
  return d;
}

// Every ESC of the line in turn until the frame turns back, as the line
// was carried before the skip index (49fab26): nothing to plan, no index
// to keep, each ESC takes its times directly. Left behind: index_stale_,
// for the next frame that skips.
Delivery Segment::carry_dense(DatagramView first, std::size_t count, Nanoseconds now) noexcept {
  Delivery d;
  const std::size_t n = escs_.size();
  if (n == 0 || !master_[0].up) [[unlikely]] return d;
  index_stale_ = true;
  if (passes_pending_) [[unlikely]] {  // frames of the skipping path passed ESCs by
    for (Esc* e : escs_) e->sync_pass();
    passes_pending_ = false;
  }
  return carry_dense_line(first, count, now);
}

// The ESCs entered are always the first `reached` (or up to the one that
// lost or destroyed the frame): their entered bits are set once, after the
// loop, not per ESC (issue 30: 10 instructions an ESC).
Delivery Segment::carry_dense_line(DatagramView first, std::size_t count, Nanoseconds now) noexcept {
  Delivery d;
  const std::size_t n = escs_.size();
  Esc* const* const escs = escs_.data();
  std::size_t reached = n;  // went on out of the last ESC's port 1 unless turned back
  Nanoseconds t = now;      // when the frame reaches ESC i's port 0
  for (std::size_t i = 0; i < n; ++i, t += out_step_) {
    Esc* esc = escs[i];
    if (!esc->port_open_[kUpstreamPort]) [[unlikely]] {
      index_.entered_first(i);
      esc->frame_at_closed_port(kUpstreamPort);  // a closed port takes nothing in
      return d;
    }
    if (!esc->process_datagrams(first, count, t)) [[unlikely]] {
      index_.entered_first(i + 1);
      d.outcome = Delivery::Outcome::Destroyed;
      return d;
    }
    const Esc::LineRoute route = esc->line_route_;
    if (route == Esc::LineRoute::Back) {
      reached = i + 1;
      break;
    }
    if (route == Esc::LineRoute::Lost) [[unlikely]] {
      index_.entered_first(i + 1);
      return d;
    }
  }
  index_.entered_first(reached);
  // Out of the last reached ESC's port 1 at `turned`; ESC i's port 1 sees
  // it back after reached - 2 - i more hops.
  const Nanoseconds turned = now + out_step_ * static_cast<std::int64_t>(reached);
  Nanoseconds back = turned + back_step_ * (static_cast<std::int64_t>(reached) - 2);
  for (std::size_t i = 0; i + 1 < reached; ++i, back -= back_step_) {
    escs[i]->dc_.on_frame_arrival(static_cast<int>(kDownstreamPort), back);
  }
  d.outcome = Delivery::Outcome::Returned;
  d.master_port = 0;
  d.at = turned + back_step_ * (static_cast<std::int64_t>(reached) - 1) - hop_delay_;
  d.processed = static_cast<unsigned>(reached);
  return d;
}

// carry_dense for a segment of one ESC (the virtual slave of most runs):
// no loop, and nothing to hand back on the way home. send takes it
// (send_one) on LinePath::OneEsc, one test for what carry_dense would ask of
// the segment (issue 30: the one-ESC FPRD 243 instructions against 205 at
// 49fab26; 195 since session 32, compiled into send_one).
// No frame ever skips on one ESC (kSkipFrom), so no pass is pending.
inline Delivery Segment::carry_one(DatagramView first, std::size_t count, Nanoseconds now) noexcept {
  Delivery d;
  Esc* const esc = escs_.front();
  index_stale_ = true;
  if (!esc->port_open_[kUpstreamPort]) [[unlikely]] {
    esc->frame_at_closed_port(kUpstreamPort);
    return d;
  }
  index_.entered_first(1);
  if (!esc->process_datagrams(first, count, now)) [[unlikely]] {
    d.outcome = Delivery::Outcome::Destroyed;
    return d;
  }
  if (esc->line_route_ == Esc::LineRoute::Lost) [[unlikely]] return d;
  d.outcome = Delivery::Outcome::Returned;
  d.master_port = 0;
  d.at = now + out_step_ - hop_delay_;
  d.processed = 1;
  return d;
}

// The ESCs accessed from outside a frame since the last one (PDI, poll,
// link, reset: Esc::touch) are read again; the ones still passive may be
// passed by (their firmware ran, they are not addressed).
template <bool kRoute>
void Segment::refresh_dirty() noexcept {
  const std::span<std::uint64_t> dirty = index_.dirty_words();
  for (std::size_t w = 0; w < dirty.size(); ++w) {
    std::uint64_t bits = dirty[w];
    if (bits == 0) continue;
    dirty[w] = 0;
    do {
      note_entered<kRoute>(w * SkipIndex::kWordBits + static_cast<std::size_t>(std::countr_zero(bits)));
      bits &= bits - 1;
    } while (bits != 0);
  }
}

bool Segment::enters_all(DatagramView first, std::size_t count) noexcept {
  std::size_t auto_increments = 0;
  DatagramView dg = first;
  for (std::size_t left = count;;) {
    const engine_detail::CommandTraits& traits =
        engine_detail::kCommandTraits[static_cast<std::uint8_t>(dg.command())];
    switch (traits.mode) {
      case Addressing::Broadcast:
        return true;
      case Addressing::AutoIncrement:
        if (traits.rmw || auto_increments++ == kMaxAutoIncrement) return true;
        break;
      case Addressing::Configured:
        if (traits.rmw) return true;
        break;
      case Addressing::None:
      case Addressing::Logical:
        break;
    }
    if (--left == 0) return false;
    dg = dg.next();
  }
}

// maps_every_esc implies the share (every span starts inside); it is asked
// first as the cheaper test for the one LRW over a whole image.
[[gnu::always_inline]] inline bool Segment::maps_most(DatagramView first, std::size_t count) noexcept {
  DatagramView dg = first;
  for (std::size_t left = count;;) {
    const engine_detail::CommandTraits& traits =
        engine_detail::kCommandTraits[static_cast<std::uint8_t>(dg.command())];
    if (traits.mode == Addressing::Logical &&
        (index_.maps_every_esc(dg.logical_address(), dg.length()) ||
         index_.spans_starting_in(dg.logical_address(), dg.length()) * kDenseShare >= escs_.size())) {
      return true;
    }
    if (--left == 0) return false;
    dg = dg.next();
  }
}

void Segment::plan(DatagramView first, std::size_t count, Nanoseconds now) noexcept {
  // On the line the n-th position is ESC n.
  mark_addressed(first, count, escs_.size(), [](std::size_t at) { return at; });
  index_.mark_due(now, out_step_);
}

// The logical bytes of each active FMMU (Section I §6: [logical_start,
// logical_start + length) holds every bit it maps), joined where they touch
// or overlap, by start; past SkipIndex::kSpans ranges the rest go into the
// last one. A datagram outside all of them makes no FMMU act (the routed
// and the bit-granular path alike), so the ESC may be passed by.
std::size_t Segment::logical_spans(const Esc& e, SkipIndex::Spans& out) noexcept {
  std::array<SkipIndex::Span, kMaxFmmus> all{};
  std::size_t n = 0;
  for (unsigned k = 0; k < e.config_.fmmu_count; ++k) {
    if ((e.fmmu_active_ & (1u << k)) == 0) continue;
    const Fmmu& f = e.fmmus_[k];
    all[n++] = SkipIndex::Span{f.logical_start, std::uint64_t{f.logical_start} + f.length};
  }
  std::sort(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(n),
            [](const SkipIndex::Span& a, const SkipIndex::Span& b) { return a.first < b.first; });
  std::size_t count = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (count > 0 && (all[k].first <= out[count - 1].end || count == out.size())) {
      out[count - 1].end = std::max(out[count - 1].end, all[k].end);
    } else {
      out[count++] = all[k];
    }
  }
  return count;
}

// The registers behind ESC i's address epoch (Esc::address_epoch_).
void Segment::read_addressing(std::size_t i) noexcept {
  const Esc& e = *escs_[i];
  EscView& v = views_[i];
  const std::uint8_t* m = e.mem_.get();
  v.address_epoch = e.address_epoch_;
  const std::uint16_t station = load_le<std::uint16_t>(m + reg::kConfiguredStationAddress);
  const bool alias_on = (m[reg::kDlControl + 3] & (bits::kDlStationAlias >> 24)) != 0;
  const std::uint16_t alias = alias_on ? load_le<std::uint16_t>(m + reg::kConfiguredStationAlias) : station;
  v.address = station | (std::uint32_t{alias} << 16);
  v.event_mask = e.ecat_event_mask_;
  v.open = e.config_.fast_paths && e.port_open_[kUpstreamPort] && !e.reset_requested_;
  v.down = e.line_route_ == Esc::LineRoute::Down;
}

template <bool kRoute>
void Segment::note_entered(std::size_t i) noexcept {
  const Esc& e = *escs_[i];
  if (views_[i].address_epoch != e.address_epoch_) [[unlikely]] read_addressing(i);
  const EscView& v = views_[i];
  SkipIndex::Passive p;
  // The IRQ field (Esc::irq_field) is 0 while the mask is, without a look
  // at the request register.
  const bool no_irq = v.event_mask == 0 || (e.ecat_event() & v.event_mask) == 0;
  if constexpr (kRoute) {
    // Port 0 open: the processing unit leaves the frame's circulating bits alone.
    p.passive = v.open && no_irq && !e.dc_.receive_latch_armed();
    if (port_mask(e) != port_masks_[i]) ++topology_epoch_;
  } else {
    p.passive = v.open && v.down && no_irq && !e.dc_.receive_latch_armed();
  }
  if (p.passive) {
    p.next_timer = e.next_timer_;
    p.station = static_cast<std::uint16_t>(v.address);
    p.alias = static_cast<std::uint16_t>(v.address >> 16);
  }
  index_.update(i, p);
  if (v.fmmu_epoch != e.fmmu_epoch_) {
    views_[i].fmmu_epoch = e.fmmu_epoch_;
    SkipIndex::Spans spans{};
    const std::size_t count = logical_spans(e, spans);
    index_.set_spans(i, spans, count);
  }
}

// Esc::apply_pass takes in only the latest frame: right as long as each
// frame reaches the same ESCs, comes back as the one before, and starts no
// earlier. Otherwise every ESC takes in the previous frame now.
void Segment::record_pass(Nanoseconds start, std::uint32_t reached, bool returned) noexcept {
  if (pass_.frame != 0 && (reached != pass_.reached || returned != pass_.returned || start < pass_.start)) {
    for (Esc* e : escs_) e->sync_pass();
  }
  pass_.frame += 1;
  passes_pending_ = true;
  pass_.start = start;
  pass_.out = out_step_;
  pass_.back = back_step_;
  pass_.reached = reached;
  pass_.returned = returned;
}

// Any topology: the frame goes from port to port as on silicon. Received at
// port p from a cable, it is taken in only if p is open; at port 0 it goes
// through the processing unit, then on in the order 3, 1, 2, 0; a closed port
// loops it back to the next one (and a closed port 0 into the processing
// unit); the first open port sends it down its cable (Section I §3.2 Table 9
// and Figure 5: out of port 0 also when every port is closed). Time advances
// by each cable's delay. A frame that keeps circling (no master port on its
// way) is dropped after every port of every ESC could have been passed twice.
Delivery Segment::carry_ports(DatagramView first, std::size_t count, Nanoseconds now, unsigned master_port) noexcept {
  Delivery d;
  if (master_port >= kMasterPorts) return d;
  const Link& entry = master_[master_port];
  if (entry.slave == kNoSlave || !entry.up) return d;
  ++frame_number_;
  return walk_ports(d, first, count, entry.slave, entry.port, now + entry.delay, 0, nullptr);
}

Delivery Segment::walk_ports(Delivery d, DatagramView first, std::size_t count, std::size_t n, unsigned p,
                             Nanoseconds t, std::size_t step, const Nanoseconds* resume) noexcept {
  const std::size_t limit = 2 * kMaxPorts * escs_.size() + 2;
  for (; step < limit; ++step) {
    Esc& e = *escs_[n];
    std::uint64_t& touched = touched_[2 * n];
    std::uint64_t& processed = touched_[2 * n + 1];
    unsigned q = p;
    bool via_unit = false;
    bool unit_done = false;  // resumed: the frame comes out of the processing unit
    // Time inside the ESC: forwarding from a port 1..3, processing through the unit.
    Nanoseconds inside{0};
    if (resume != nullptr) [[unlikely]] {
      q = kUpstreamPort;
      via_unit = true;
      unit_done = true;
      inside = *resume;
      resume = nullptr;
    } else {
      if (touched != frame_number_) {
        touched = frame_number_;
        e.dc_.begin_frame();
      }
      if (!e.port_open_[p]) {
        e.frame_at_closed_port(p);  // a closed port takes nothing in
        return d;
      }
      if (p != kUpstreamPort) {
        if (processed == frame_number_) {
          e.dc_.on_frame_arrival(static_cast<int>(p), t);
        } else {
          e.dc_.on_arrival_before_processing(static_cast<int>(p), t);
        }
      }
      inside = p == kUpstreamPort ? Nanoseconds{0} : inner_[n].forwarding[p];
    }
    for (;;) {
      if (q == kUpstreamPort && !unit_done) {
        if (via_unit) break;  // every port closed: out of port 0
        via_unit = true;
        processed = frame_number_;
        ++d.processed;
        if (!e.process_datagrams(first, count, t + inside)) {
          e.count_processing_unit_error();  // circulating frame (Section I §14.1 Table 51)
          d.outcome = Delivery::Outcome::Destroyed;
          return d;
        }
        inside += inner_[n].processing;
      }
      unit_done = false;
      q = kNextPort[q];
      if (e.port_open_[q]) break;
    }
    const Link& out = links_[n][q];
    if (out.slave == kNoSlave || !out.up) return d;  // open with nothing connected: lost
    t += inside + out.delay;
    if (out.slave == kMasterSlave) {
      d.outcome = Delivery::Outcome::Returned;
      d.master_port = out.port;
      d.at = t;
      return d;
    }
    n = out.slave;
    p = out.port;
  }
  d.outcome = Delivery::Outcome::Destroyed;
  return d;
}

std::optional<Nanoseconds> Segment::poll(Nanoseconds now) noexcept {
  std::optional<Nanoseconds> next;
  for (Esc* esc : escs_) {
    auto t = esc->poll(now);
    if (t && (!next || *t < *next)) next = t;
  }
  return next;
}

void Segment::note_entered_route(std::size_t i) noexcept { note_entered<true>(i); }

template void Segment::refresh_dirty<false>() noexcept;
template void Segment::refresh_dirty<true>() noexcept;

}  // namespace ecat::esc
