// Broken frames through a Segment: cables that corrupt frames, frames the
// processing unit rejects, and the error counters each ESC keeps on the way
// (Section I §14 "Error counters": Table 50, §14.1 Table 51, §14.2 "Errors
// and forwarded errors"; Section II 0x0300-0x030C).
//
// The ESC that first finds an error (a bad FCS or a physical-layer symbol
// error at a port's auto-forwarder, a datagram structure its processing unit
// rejects) counts it as its own, discards the frame's register operations,
// makes the outgoing CRC bad and appends a marker nibble; every later ESC
// sees the marker and counts a forwarded error at the port where the frame
// enters, and 0x030C when it passes its processing unit. The master gets a
// frame with a bad FCS and drops it.
#include <algorithm>

#include "esc/datagram_engine.hpp"
#include "esc/segment.hpp"

namespace ecat::esc {

namespace {
using segment_detail::kNextPort;

// What the frame carries from cable to cable.
enum class FrameFault : std::uint8_t {
  None,        // intact
  Unparsable,  // intact on the wire, but a processing unit will reject its datagrams
  Crc,         // corrupted on the last cable: the receiving port's own error
  RxError,     // the same, with a symbol error the PHY reports
  Marked,      // marked as broken by an earlier ESC: a forwarded error
};

bool broken(FrameFault f) noexcept { return f != FrameFault::None && f != FrameFault::Unparsable; }
}  // namespace

Segment::CableFaultState* Segment::fault_on(std::size_t slave, unsigned port) noexcept {
  for (CableFaultState& f : faults_) {
    if (f.slave == slave && f.port == port) return &f;
    const Link& l = links_[f.slave][f.port];  // the cable's other end
    if (l.slave == slave && l.port == port) return &f;
  }
  return nullptr;
}

bool Segment::corrupt_link(std::size_t slave, unsigned port, unsigned frames, CableFault fault) noexcept {
  if (slave >= escs_.size() || port >= kMaxPorts || links_[slave][port].slave == kNoSlave) return false;
  if (CableFaultState* f = fault_on(slave, port)) {
    f->left = frames;
    f->fault = fault;
  } else if (frames != 0) {
    faults_.push_back(CableFaultState{static_cast<std::uint32_t>(slave), static_cast<std::uint8_t>(port), fault,
                                      frames, 0});
  }
  std::erase_if(faults_, [](const CableFaultState& f) { return f.left == 0; });
  refresh_path();
  return true;
}

unsigned Segment::corruption_pending(std::size_t slave, unsigned port) const noexcept {
  if (slave >= escs_.size() || port >= kMaxPorts) return 0;
  const Link& l = links_[slave][port];
  for (const CableFaultState& f : faults_) {
    if ((f.slave == slave && f.port == port) || (f.slave == l.slave && f.port == l.port)) return f.left;
  }
  return 0;
}

// carry_ports, plus: each cable the frame crosses may corrupt it (once per
// frame); each open port it enters counts what its auto-forwarder sees; a
// processing unit passes a broken frame without touching it (register
// operations discarded, Section I §14.1) and counts 0x030C.
Delivery Segment::carry_faulty(DatagramView first, std::size_t count, Nanoseconds now, unsigned master_port,
                               bool parsed) noexcept {
  Delivery d;
  if (master_port >= kMasterPorts) return d;
  const Link& entry = master_[master_port];
  if (entry.slave == kNoSlave || !entry.up) return d;
  ++frame_number_;
  FrameFault fault = parsed ? FrameFault::None : FrameFault::Unparsable;
  // The frame crosses the cable on (slave, port): a faulty cable corrupts
  // it unless it is already broken (the marker survives) or was hit before.
  auto cross = [&](std::size_t slave, unsigned port) noexcept {
    CableFaultState* f = faults_.empty() ? nullptr : fault_on(slave, port);
    if (f == nullptr || f->hit_frame == frame_number_) return;
    f->hit_frame = frame_number_;
    if (!broken(fault)) fault = f->fault == CableFault::RxError ? FrameFault::RxError : FrameFault::Crc;
    if (--f->left == 0) {
      std::erase_if(faults_, [](const CableFaultState& s) { return s.left == 0; });
      refresh_path();
    }
  };
  std::size_t n = entry.slave;
  unsigned p = entry.port;
  cross(n, p);
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
      if (!broken(fault)) e.frame_at_closed_port(p);  // only a valid frame opens an Auto-close port
      return d;
    }
    // The auto-forwarder of port p (Section I §14.1 Table 51).
    switch (fault) {
      case FrameFault::Crc:
        e.count_port_error(p, Esc::PortError::InvalidFrame);
        fault = FrameFault::Marked;
        break;
      case FrameFault::RxError:
        e.count_port_error(p, Esc::PortError::PhysicalLayer);
        fault = FrameFault::Marked;
        break;
      case FrameFault::Marked:
        e.count_port_error(p, Esc::PortError::Forwarded);
        break;
      case FrameFault::None:
      case FrameFault::Unparsable:
        break;
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
    Nanoseconds inside = p == kUpstreamPort ? Nanoseconds{0} : inner_[n].forwarding[p];
    for (;;) {
      if (q == kUpstreamPort) {
        if (via_unit) break;  // every port closed: out of port 0
        via_unit = true;
        processed = frame_number_;
        const Nanoseconds at_unit = t + inside;
        inside += inner_[n].processing;
        if (fault != FrameFault::None) {
          // The unit finds the error (its own port's, a forwarded one, or
          // the datagram structure) and discards the frame's operations.
          e.count_processing_unit_error();
          fault = FrameFault::Marked;
        } else {
          ++d.processed;
          if (!e.process_datagrams(first, count, at_unit)) {
            e.count_processing_unit_error();  // circulating frame
            d.outcome = Delivery::Outcome::Destroyed;
            return d;
          }
        }
      }
      q = kNextPort[q];
      if (e.port_open_[q]) break;
    }
    const Link& out = links_[n][q];
    if (out.slave == kNoSlave || !out.up) return d;  // open with nothing connected: lost
    cross(n, q);
    t += inside + out.delay;
    if (out.slave == kMasterSlave) {
      d.outcome = broken(fault) ? Delivery::Outcome::Corrupted : Delivery::Outcome::Returned;
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

}  // namespace ecat::esc
