// Topology from DL status and port receive times (docs/master.md "Topology
// and DC delays in trees"; facts: masters.md §1.1, esc-registers.md §1.4, §4.7).
#include "master/topology.hpp"

#include <bit>

namespace ecat::master {

namespace {

constexpr std::uint8_t port_bit(unsigned port) noexcept { return static_cast<std::uint8_t>(1u << port); }

// Index of `port` in kPortProcessingOrder.
constexpr unsigned order_index(unsigned port) noexcept {
  for (unsigned i = 0; i < kEscPortCount; ++i) {
    if (kPortProcessingOrder[i] == port) return i;
  }
  return 0;
}

// 32-bit local times wrap (≈ 4.3 s): a difference is taken modulo 2^32.
constexpr std::int64_t elapsed(std::uint32_t from, std::uint32_t to) noexcept {
  return static_cast<std::int32_t>(to - from);
}

}  // namespace

std::uint8_t active_ports_from_dl_status(std::uint16_t dl_status) noexcept {
  std::uint8_t active = 0;
  for (unsigned n = 0; n < kEscPortCount; ++n) {
    const bool loop_closed = (dl_status >> (kDlLoopClosedShift + 2 * n)) & 1u;
    const bool communication = (dl_status >> (kDlCommunicationShift + 2 * n)) & 1u;
    if (!loop_closed && communication) active |= port_bit(n);
  }
  return active;
}

unsigned active_port_count(std::uint8_t active) noexcept {
  return static_cast<unsigned>(std::popcount(static_cast<unsigned>(active & 0x0F)));
}

unsigned next_active_port(std::uint8_t active, unsigned port) noexcept {
  const unsigned at = order_index(port);
  for (unsigned step = 1; step < kEscPortCount; ++step) {
    const unsigned p = kPortProcessingOrder[(at + step) % kEscPortCount];
    if (active & port_bit(p)) return p;
  }
  return port;
}

unsigned previous_active_port(std::uint8_t active, unsigned port) noexcept {
  const unsigned at = order_index(port);
  for (unsigned step = 1; step < kEscPortCount; ++step) {
    const unsigned p = kPortProcessingOrder[(at + kEscPortCount - step) % kEscPortCount];
    if (active & port_bit(p)) return p;
  }
  return port;
}

unsigned entry_port(std::uint8_t active, const std::optional<PortTimes>& times) noexcept {
  if (times) {
    for (unsigned p : kPortProcessingOrder) {
      if ((active & port_bit(p)) == 0) continue;
      bool first = true;
      for (unsigned q = 0; q < kEscPortCount; ++q) {
        if (q != p && (active & port_bit(q)) != 0 && elapsed((*times)[p], (*times)[q]) < 0) first = false;
      }
      if (first) return p;
    }
  }
  for (unsigned p : kPortProcessingOrder) {
    if (active & port_bit(p)) return p;
  }
  return 0;
}

std::vector<SlaveTopology> compute_topology(std::span<const TopologyInput> slaves) {
  std::vector<SlaveTopology> out(slaves.size());
  // Slaves whose subtrees are still being walked, each with the ports not yet
  // given to a child (the depth-first walk of the frame).
  std::vector<std::size_t> open;
  std::vector<std::uint8_t> unused(slaves.size(), 0);
  for (std::size_t i = 0; i < slaves.size(); ++i) {
    SlaveTopology& t = out[i];
    t.active_ports = active_ports_from_dl_status(slaves[i].dl_status);
    if (t.active_ports == 0) t.active_ports = port_bit(0);
    t.entry_port = entry_port(t.active_ports, slaves[i].port_times);
    while (!open.empty() && unused[open.back()] == 0) open.pop_back();
    if (!open.empty()) {
      const std::size_t parent = open.back();
      // The parent's next unused port after its entry port, in processing order.
      unsigned port = out[parent].entry_port;
      do {
        port = next_active_port(out[parent].active_ports, port);
      } while ((unused[parent] & port_bit(port)) == 0);
      unused[parent] = static_cast<std::uint8_t>(unused[parent] & ~port_bit(port));
      t.parent = parent;
      t.parent_port = port;
    }
    unused[i] = static_cast<std::uint8_t>(t.active_ports & ~port_bit(t.entry_port));
    if (unused[i] != 0) open.push_back(i);
  }
  for (std::size_t i = 0; i < slaves.size(); ++i) out[i].open_end_ports = unused[i];
  return out;
}

}  // namespace ecat::master
