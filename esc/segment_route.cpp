// Frames through trees and rings that pass the ESCs they do not address
// (issue 30 item 2; docs/esc.md "Skipping ESCs a frame does not address").
//
// On a line the frame's way is the line itself. On a tree or ring it is
// whatever the port walk (Segment::carry_ports, Section I §3.2 Table 9)
// makes of the ports' states and cables, and that does not change from one
// frame to the next unless a port opens or closes or a cable goes up or
// down. So the walk is done once per master port without any frame
// (build_route): the order of the processing units the frame passes, when
// it reaches each of them and every other port on its way, and where it
// ends. A frame then enters, in that order, only the ESCs it addresses or
// maps and the ones not passive (SkipIndex, as on the line); each entered
// ESC gets exactly the calls the walk makes on it (its arrivals at ports
// 1-3 before its unit, the unit, the arrivals after it). The ESCs passed by
// take in the frame's times when next looked at (RoutePass, Esc::sync_pass).
//
// The route is stale when an ESC's open ports differ from the ones it was
// built with (read again whenever an ESC is entered or was accessed: the
// index's refresh), or a cable's state changed (set_link), or a port walk
// ran. If an entered ESC's ports change under the frame (a write to its
// loop control, a reset), the events of the route before it are done in
// full on every ESC and the port walk carries the frame on from that
// ESC's processing unit (materialize, walk_ports).
#include "esc/segment.hpp"

#include "esc/datagram_engine.hpp"
#include "esc/segment_marking.hpp"

#include <algorithm>
#include <bit>

namespace ecat::esc {

using segment_detail::kNextPort;

namespace {
constexpr Nanoseconds kNoTime = RoutePass::kNoTime;
Nanoseconds later(Nanoseconds seen, Nanoseconds t) noexcept { return seen == kNoTime || t > seen ? t : seen; }
}  // namespace

void Segment::check_dirty_ports() noexcept {
  const std::span<std::uint64_t> dirty = index_.dirty_words();
  for (std::size_t w = 0; w < dirty.size(); ++w) {
    for (std::uint64_t bits = dirty[w]; bits != 0; bits &= bits - 1) {
      const std::size_t i = w * SkipIndex::kWordBits + static_cast<std::size_t>(std::countr_zero(bits));
      if (port_mask(*escs_[i]) != port_masks_[i]) {
        ++topology_epoch_;
        return;
      }
    }
  }
}

// carry_ports without a frame and without touching any ESC: the same
// steps, recorded. A route that passes a processing unit twice or circles
// until the walk's limit is not used (the port walk destroys such frames).
void Segment::build_route(unsigned master_port) {
  for (Esc* e : escs_) e->sync_pass();  // the times of frames passed by under the old route first
  const std::size_t size = escs_.size();
  for (std::size_t i = 0; i < size; ++i) port_masks_[i] = port_mask(*escs_[i]);
  Route& r = routes_[master_port];
  r.built = true;
  r.usable = true;
  r.epoch = topology_epoch_;
  r.outcome = Delivery::Outcome::Lost;
  r.out_port = 0;
  r.out_at = Nanoseconds{0};
  r.closed_slave = kNoSlave;
  r.closed_port = 0;
  r.last_unit = Nanoseconds{0};
  r.events.clear();
  r.units.clear();
  r.unit_event.clear();
  r.ordinal.assign(size, kNoSlave);
  r.unit_at.assign(size, kNoTime);
  r.seen_at.assign(size, kNoTime);
  const Link& entry = master_[master_port];
  if (entry.slave != kNoSlave && entry.up) {
    std::size_t n = entry.slave;
    unsigned p = entry.port;
    Nanoseconds t = entry.delay;
    const std::size_t limit = 2 * kMaxPorts * size + 2;
    bool ended = false;
    for (std::size_t step = 0; step < limit && !ended; ++step) {
      const Esc& e = *escs_[n];
      if (!e.port_open_[p]) {
        r.closed_slave = static_cast<std::uint32_t>(n);
        r.closed_port = static_cast<std::uint8_t>(p);
        ended = true;
        break;
      }
      if (p != kUpstreamPort) {
        RouteEvent ev;
        ev.slave = static_cast<std::uint32_t>(n);
        ev.port = static_cast<std::uint8_t>(p);
        ev.kind = RouteEvent::Kind::Arrive;
        ev.after_unit = r.ordinal[n] != kNoSlave;
        ev.step = static_cast<std::uint32_t>(step);
        ev.t = t;
        r.events.push_back(ev);
        r.seen_at[n] = later(r.seen_at[n], t);
      }
      unsigned q = p;
      bool via_unit = false;
      Nanoseconds inside = p == kUpstreamPort ? Nanoseconds{0} : inner_[n].forwarding[p];
      for (;;) {
        if (q == kUpstreamPort) {
          if (via_unit) break;
          via_unit = true;
          if (r.ordinal[n] != kNoSlave) {  // a processing unit twice: a circulating frame
            r.usable = false;
            return;
          }
          r.ordinal[n] = static_cast<std::uint32_t>(r.units.size());
          r.units.push_back(static_cast<std::uint32_t>(n));
          r.unit_event.push_back(static_cast<std::uint32_t>(r.events.size()));
          RouteEvent ev;
          ev.slave = static_cast<std::uint32_t>(n);
          ev.port = static_cast<std::uint8_t>(p);
          ev.kind = RouteEvent::Kind::Unit;
          ev.step = static_cast<std::uint32_t>(step);
          ev.t = t + inside;
          ev.arrived = t;
          r.events.push_back(ev);
          r.unit_at[n] = t + inside;
          r.seen_at[n] = later(r.seen_at[n], t + inside);
          r.last_unit = std::max(r.last_unit, t + inside);
          inside += inner_[n].processing;
        }
        q = kNextPort[q];
        if (e.port_open_[q]) break;
      }
      const Link& out = links_[n][q];
      if (out.slave == kNoSlave || !out.up) {  // open with nothing connected: lost
        ended = true;
        break;
      }
      t += inside + out.delay;
      if (out.slave == kMasterSlave) {
        r.outcome = Delivery::Outcome::Returned;
        r.out_port = out.port;
        r.out_at = t;
        ended = true;
        break;
      }
      n = out.slave;
      p = out.port;
    }
    if (!ended) {  // circling: the walk destroys it at its limit
      r.usable = false;
      return;
    }
  }
  // Each slave's events in order, for the ESCs a frame enters.
  r.begin.assign(size + 1, 0);
  for (const RouteEvent& ev : r.events) ++r.begin[ev.slave + 1];
  for (std::size_t i = 0; i < size; ++i) r.begin[i + 1] += r.begin[i];
  r.by_slave.resize(r.events.size());
  std::vector<std::uint32_t> at(r.begin.begin(), r.begin.end() - 1);
  for (std::size_t k = 0; k < r.events.size(); ++k) r.by_slave[at[r.events[k].slave]++] = static_cast<std::uint32_t>(k);
  unit_visit_.assign((size + SkipIndex::kWordBits - 1) / SkipIndex::kWordBits + 1, 0);  // either route's units
}

// The ESCs a frame that does not enter all must enter, as plan() does on
// the line; an APxx addresses the ESC whose unit is the ADP-th on the route.
void Segment::plan_route(const Route& r, DatagramView first, std::size_t count, Nanoseconds now) noexcept {
  mark_addressed(first, count, r.units.size(), [&r](std::size_t at) { return r.units[at]; });
  index_.mark_due_at(now, r.unit_at.data(), kNoTime, r.last_unit);
}

// The route's events before event `at` that the frame has not done yet,
// as the port walk does them: on the ESCs passed by, every arrival and
// the unit's times (a passive ESC's unit changes nothing else); on the
// entered ones, the arrivals after their unit. Leaves touched_ as the
// walk would (for walk_ports to go on).
void Segment::materialize(const Route& r, std::size_t at, Nanoseconds now) noexcept {
  for (Esc* e : escs_) e->sync_pass();  // frames passed by before this one
  for (std::size_t k = 0; k < at; ++k) {
    const RouteEvent& ev = r.events[k];
    Esc& e = *escs_[ev.slave];
    std::uint64_t& touched = touched_[2 * ev.slave];
    std::uint64_t& processed = touched_[2 * ev.slave + 1];
    const Nanoseconds t = now + ev.t;
    if (ev.kind == RouteEvent::Kind::Unit) {
      if (processed == frame_number_) continue;  // entered: done
      if (touched != frame_number_) {
        touched = frame_number_;
        e.dc_.begin_frame();
      }
      processed = frame_number_;
      e.now_ = t;
      e.dc_.on_frame_arrival(static_cast<int>(kUpstreamPort), t);
      continue;
    }
    if (ev.after_unit) {
      e.dc_.on_frame_arrival(static_cast<int>(ev.port), t);
      continue;
    }
    if (processed == frame_number_) continue;  // entered: done before its unit
    if (touched != frame_number_) {
      touched = frame_number_;
      e.dc_.begin_frame();
    }
    e.dc_.on_arrival_before_processing(static_cast<int>(ev.port), t);
  }
}

void Segment::record_route_pass(unsigned master_port, Nanoseconds start) noexcept {
  RoutePass& rp = route_passes_[master_port];
  // A frame of this port that starts earlier than its last one: every ESC
  // takes in the last one now (Esc::apply_route_passes keeps the latest only).
  if (rp.frame != 0 && start < rp.start) {
    for (Esc* e : escs_) e->sync_pass();
  }
  const Route& r = routes_[master_port];
  pass_.routes = route_passes_.data();
  pass_.frame += 1;
  rp.frame = pass_.frame;
  rp.start = start;
  rp.unit_at = r.unit_at.data();
  rp.seen_at = r.seen_at.data();
}

// As on the line (carry_line): a frame that enters every unit reads the
// ESCs touched since the last frame as it enters them (only their ports
// first), and the two kinds are two instances of one loop.
Delivery Segment::carry_route(DatagramView first, std::size_t count, Nanoseconds now, unsigned master_port) noexcept {
  if (master_port >= kMasterPorts) return Delivery{};
  return enters_all(first, count) ? carry_route_as<true>(first, count, now, master_port)
                                  : carry_route_as<false>(first, count, now, master_port);
}

template <bool all>
Delivery Segment::carry_route_as(DatagramView first, std::size_t count, Nanoseconds now,
                                 unsigned master_port) noexcept {
  Delivery d;
  if constexpr (all) {
    check_dirty_ports();
  } else {
    refresh_dirty<true>();
  }
  Route& r = routes_[master_port];
  if (!r.built || r.epoch != topology_epoch_) build_route(master_port);
  if (!r.usable) [[unlikely]] return carry_every(first, count, now, master_port);
  const Link& entry = master_[master_port];
  if (entry.slave == kNoSlave || !entry.up) return d;
  ++frame_number_;
  if constexpr (!all) {
    plan_route(r, first, count, now);
    for (std::size_t i = index_.next(0); i < escs_.size(); i = index_.next(i + 1)) {
      const std::uint32_t o = r.ordinal[i];
      if (o != kNoSlave) unit_visit_[o / SkipIndex::kWordBits] |= SkipIndex::bit(o);
    }
  }
  const std::size_t units = r.units.size();
  std::size_t visited = 0;
  std::size_t o = 0;
  for (;;) {
    if constexpr (all) {
      if (o >= units) break;
    } else {
      // The next marked unit in route order (the bits are cleared as taken).
      std::size_t w = o / SkipIndex::kWordBits;
      while (w < unit_visit_.size() && unit_visit_[w] == 0) ++w;
      if (w >= unit_visit_.size()) break;
      o = w * SkipIndex::kWordBits + static_cast<std::size_t>(std::countr_zero(unit_visit_[w]));
      unit_visit_[w] &= unit_visit_[w] - 1;
      if (o >= units) break;
    }
    const std::size_t i = r.units[o];
    const RouteEvent& u = r.events[r.unit_event[o]];
    Esc* esc = escs_[i];
    if constexpr (!all) {  // as carry_line: the units a few ahead in route order
      if (o + kPrefetchObjectAhead < units) escs_[r.units[o + kPrefetchObjectAhead]]->prefetch_pass_object();
      if (o + kPrefetchTargetsAhead < units) escs_[r.units[o + kPrefetchTargetsAhead]]->prefetch_pass_targets();
    }
    esc->sync_pass();
    if constexpr (!all) {
      for (std::size_t k = 0; k < auto_increments_; ++k) {
        auto_increment_[k].datagram.set_adp(static_cast<std::uint16_t>(auto_increment_[k].adp + o));
      }
    }
    index_.entered(i);
    visited_[visited++] = static_cast<std::uint32_t>(i);
    touched_[2 * i] = frame_number_;
    touched_[2 * i + 1] = frame_number_;
    esc->dc_.begin_frame();
    for (std::uint32_t k = r.begin[i]; k < r.begin[i + 1]; ++k) {  // its arrivals before the unit
      const RouteEvent& ev = r.events[r.by_slave[k]];
      if (ev.kind == RouteEvent::Kind::Unit) break;
      esc->dc_.on_arrival_before_processing(static_cast<int>(ev.port), now + ev.t);
    }
    if (!esc->process_datagrams(first, count, now + u.t)) [[unlikely]] {
      esc->count_processing_unit_error();  // circulating frame (Section I §14.1 Table 51)
      materialize(r, r.unit_event[o], now);
      std::fill(unit_visit_.begin(), unit_visit_.end(), 0);
      ++topology_epoch_;
      index_.must_visit_all();
      index_.entered_all();
      d.outcome = Delivery::Outcome::Destroyed;
      d.processed = static_cast<unsigned>(o + 1);
      return d;
    }
    const std::uint64_t epoch = topology_epoch_;
    note_entered_route(i);
    if constexpr (all) index_.dirty_words()[i / SkipIndex::kWordBits] &= ~SkipIndex::bit(i);
    if (topology_epoch_ != epoch) [[unlikely]] {
      // Its ports changed under the frame: the port walk carries it on from here.
      materialize(r, r.unit_event[o], now);
      std::fill(unit_visit_.begin(), unit_visit_.end(), 0);
      const Nanoseconds inside = (u.t - u.arrived) + inner_[i].processing;
      d.processed = static_cast<unsigned>(o + 1);
      d = walk_ports(d, first, count, i, u.port, now + u.arrived, u.step, &inside);
      index_.must_visit_all();
      index_.entered_all();
      return d;
    }
    if constexpr (all) ++o;
  }
  if constexpr (!all) {
    for (std::size_t k = 0; k < auto_increments_; ++k) {
      auto_increment_[k].datagram.set_adp(static_cast<std::uint16_t>(auto_increment_[k].adp + units));
    }
  }
  // The entered ESCs' arrivals after their unit (on the way back, or on to
  // the master through them), which latch receive times when armed.
  for (std::size_t k = 0; k < visited; ++k) {
    const std::size_t i = visited_[k];
    Esc* esc = escs_[i];
    for (std::uint32_t e = r.begin[i]; e < r.begin[i + 1]; ++e) {
      const RouteEvent& ev = r.events[r.by_slave[e]];
      if (ev.kind == RouteEvent::Kind::Arrive && ev.after_unit) {
        esc->dc_.on_frame_arrival(static_cast<int>(ev.port), now + ev.t);
      }
    }
  }
  if (r.closed_slave != kNoSlave) {  // sent into a closed port: it takes nothing in
    Esc& e = *escs_[r.closed_slave];
    e.frame_at_closed_port(r.closed_port);
    if (port_mask(e) != port_masks_[r.closed_slave]) ++topology_epoch_;
  }
  record_route_pass(master_port, now);
  for (std::size_t k = 0; k < visited; ++k) escs_[visited_[k]]->hook_.synced = pass_.frame;
  if constexpr (all) refresh_dirty<true>();  // the ESCs it did not enter (or that were touched while it passed)
  d.outcome = r.outcome;
  d.processed = static_cast<unsigned>(units);
  if (r.outcome == Delivery::Outcome::Returned) {
    d.master_port = static_cast<std::uint8_t>(r.out_port);
    d.at = now + r.out_at;
  }
  return d;
}

}  // namespace ecat::esc
