// Frame transport through ESCs wired as a line, a tree or a ring
// (Section I §3.2 frame processing order, §3.4 loop control).
#include "esc/segment.hpp"

#include "esc/datagram_engine.hpp"

namespace ecat::esc {

using segment_detail::kNextPort;

std::size_t Segment::append(Esc& esc) {
  escs_.push_back(&esc);
  const InnerDelay inner{esc.config().processing_delay, esc.config().forwarding_delay};
  inner_.push_back(inner);
  if (inner.processing != Nanoseconds{0} || inner.forwarding != Nanoseconds{0}) line_ = false;  // carry_ports adds them
  links_.emplace_back();
  touched_.push_back(0);
  touched_.push_back(0);  // two words per slave: touched, processed
  return escs_.size() - 1;
}

void Segment::cable(std::size_t a, unsigned pa, std::size_t b, unsigned pb, Nanoseconds delay) {
  links_[a][pa] = Link{static_cast<std::uint32_t>(b), static_cast<std::uint8_t>(pb), true, delay};
  links_[b][pb] = Link{static_cast<std::uint32_t>(a), static_cast<std::uint8_t>(pa), true, delay};
  escs_[a]->set_link(pa, true);
  escs_[b]->set_link(pb, true);
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
  escs_[slave]->set_link(port, true);
}

bool Segment::set_link(std::size_t slave, unsigned port, bool up) noexcept {
  if (slave >= escs_.size() || port >= kMaxPorts) return false;
  Link& l = links_[slave][port];
  if (l.slave == kNoSlave) return false;
  if (l.up == up) return true;
  l.up = up;
  escs_[slave]->set_link(port, up);
  if (l.slave == kMasterSlave) {
    master_[l.port].up = up;
  } else {
    links_[l.slave][l.port].up = up;
    escs_[l.slave]->set_link(l.port, up);
  }
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
// pass (esc/datagram_engine.hpp, inline) walks the datagrams in place.
Delivery Segment::send(std::span<std::uint8_t> frame, Nanoseconds now, unsigned master_port) noexcept {
  const detail::EthercatAt at = detail::find_ethercat(frame);
  ValidatedDatagrams valid;
  if (at.ok) [[likely]] {
    valid = validate_ethercat(frame, at.offset);
  } else {
    valid.error = at.error;
  }
  if (valid.count == 0) [[unlikely]] {
    last_error_ = valid.error;
    ++dropped_;
    if (valid.error != FrameError::NotEtherCat) {
      // The first processing unit rejects the datagram structure (0x030C) and
      // marks the frame; every later port counts a forwarded error (0x0308+n)
      // and every later unit 0x030C (Section I §14.1 Table 51, §14.2).
      (void)carry_faulty(DatagramView{}, 0, now, master_port, false);
    }
    Delivery d;
    d.outcome = Delivery::Outcome::Malformed;
    return d;
  }
  const DatagramView first(valid.first);
  const Delivery d = !faults_.empty()             ? carry_faulty(first, valid.count, now, master_port, true)
                     : line_ && master_port == 0 ? carry_line(first, valid.count, now)
                                                 : carry_ports(first, valid.count, now, master_port);
  if (!d.returned()) [[unlikely]] {
    ++dropped_;
    return d;
  }
  // Every frame that passed a processing unit leaves with SOURCE_MAC[1] set (Section I §3.2).
  if (d.processed != 0) frame[kMacSize] = static_cast<std::uint8_t>(frame[kMacSize] | kSourceMacProcessedBit);
  ++processed_;
  return d;
}

// A line: each ESC's port 0 faces the master. Ports 2 and 3 have no
// neighbour, so after the processing unit the frame goes on out of port 1,
// back (ports 3, 1, 2 closed) or is lost (Esc::line_route_, kept by
// update_ports); no port walk per ESC.
Delivery Segment::carry_line(DatagramView first, std::size_t count, Nanoseconds now) noexcept {
  Delivery d;
  if (escs_.empty() || !master_[0].up) [[unlikely]] return d;
  std::size_t reached = 0;
  Nanoseconds t = now;  // when the frame reaches the next ESC's port 0
  for (Esc* esc : escs_) {
    if (!esc->port_open_[kUpstreamPort]) [[unlikely]] {
      esc->frame_at_closed_port(kUpstreamPort);  // a closed port takes nothing in
      return d;
    }
    ++reached;
    if (!esc->process_datagrams(first, count, t)) [[unlikely]] {
      d.outcome = Delivery::Outcome::Destroyed;
      return d;
    }
    t += hop_delay_;
    const Esc::LineRoute route = esc->line_route_;
    if (route == Esc::LineRoute::Back) break;  // closed: the frame turns back here
    if (route == Esc::LineRoute::Lost) [[unlikely]] return d;  // forced open with nothing connected
  }
  // On the way back the frame passes each earlier slave's port 1.
  // After the last reached ESC (reached - 1 hops out) it takes as many back:
  // ESC i sees it at 2 (reached - 1) - i hops.
  const Nanoseconds round = hop_delay_ * static_cast<std::int64_t>(2 * (reached - 1));
  if (reached > 1) {
    Nanoseconds back = now + round;
    for (std::size_t i = 0; i + 1 < reached; ++i) {
      escs_[i]->dc_.on_frame_arrival(static_cast<int>(kDownstreamPort), back);
      back -= hop_delay_;
    }
  }
  d.outcome = Delivery::Outcome::Returned;
  d.master_port = 0;
  d.at = now + round;
  d.processed = static_cast<unsigned>(reached);
  return d;
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
  std::size_t n = entry.slave;
  unsigned p = entry.port;
  Nanoseconds t = now + entry.delay;
  const std::size_t limit = 2 * kMaxPorts * escs_.size() + 2;
  for (std::size_t step = 0; step < limit; ++step) {
    Esc& e = *escs_[n];
    std::uint64_t& touched = touched_[2 * n];
    std::uint64_t& processed = touched_[2 * n + 1];
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
    unsigned q = p;
    bool via_unit = false;
    // Time inside the ESC: forwarding from a port 1..3, processing through the unit.
    Nanoseconds inside = p == kUpstreamPort ? Nanoseconds{0} : inner_[n].forwarding;
    for (;;) {
      if (q == kUpstreamPort) {
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

}  // namespace ecat::esc
