// Where each slave sits in the segment: its parent slave, the parent's port
// it hangs on, its active ports and its entry port, computed from DL status
// 0x0110 (and, when DC is there, the port receive times 0x0900-0x090F) the
// way SOEM (ecx_config_init, ecx_configdc) and IgH (ec_master_calc_topology_rec,
// ports 0 -> 3 -> 1 -> 2 since its upstream-port patch) do it. Pure
// functions over values: the master calls them after the scan and in
// configure_dc, and a test can call them on register values it read itself
// (docs/master.md "Topology and DC delays in trees").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace ecat::master {

inline constexpr unsigned kEscPortCount = 4;

// ESC datasheet Section I "Frame processing" (ETG.1000.4 §4.3): a 4-port ESC
// takes a frame in on port 0 through the EtherCAT processing unit, then
// forwards it port 3 -> port 1 -> port 2 -> back out of port 0. Closed or
// absent ports are skipped. The order is cyclic.
inline constexpr std::array<unsigned, kEscPortCount> kPortProcessingOrder{0, 3, 1, 2};

// DL status 0x0110 (ESC datasheet Section II; esc-registers.md §4.7):
// bit 8+2n loop port n closed, bit 9+2n communication on port n.
inline constexpr unsigned kDlLoopClosedShift = 8;
inline constexpr unsigned kDlCommunicationShift = 9;

// Bit n set = port n open with communication established (SOEM "activeports":
// loop bit 0 and communication bit 1 for that port, masters.md §1.1).
std::uint8_t active_ports_from_dl_status(std::uint16_t dl_status) noexcept;
// The next / previous port of `port` among `active` in the processing order
// 0 -> 3 -> 1 -> 2 -> 0 (cyclic); `port` itself when no other port is active.
unsigned next_active_port(std::uint8_t active, unsigned port) noexcept;
unsigned previous_active_port(std::uint8_t active, unsigned port) noexcept;
unsigned active_port_count(std::uint8_t active) noexcept;

// Receive times latched by a write to 0x0900 (0x0900, 0x0904, 0x0908, 0x090C:
// ports 0..3), local time of that ESC, 32 bit.
using PortTimes = std::array<std::uint32_t, kEscPortCount>;

// What the computation needs of one slave, in auto-increment (position) order.
struct TopologyInput {
  std::uint16_t dl_status = 0;
  std::optional<PortTimes> port_times;  // when DC was latched (DC slaves)
};

struct SlaveTopology {
  std::uint8_t active_ports = 0;       // bit n: port n open with communication
  unsigned entry_port = 0;             // the port the frame from the master comes in on
  std::optional<std::size_t> parent;   // position of the parent slave; empty = hangs on the master
  unsigned parent_port = 0;            // the parent's port this slave hangs on (0 for the first slave)
  std::uint8_t open_end_ports = 0;     // active ports with no slave behind them (e.g. to a redundant master port)
  unsigned port_count() const noexcept { return active_port_count(active_ports); }
};

// The entry port: with port times, the active port whose time comes first
// (every other active port latched later, 32-bit wrap safe; SOEM takes the
// lowest time); without, the first active port in the processing order
// starting at port 0 (port 0 on every normally wired slave).
unsigned entry_port(std::uint8_t active, const std::optional<PortTimes>& times) noexcept;

// Position order is the order the frame meets the slaves, i.e. a depth-first
// walk of the tree visiting each slave's ports in processing order after its
// entry port. So slave i hangs on the most recent earlier slave that still
// has an unused active port, on the first such port in processing order
// (the same parents as SOEM's backward count of end points and split points,
// and the same ports as IgH's walk). A slave whose DL status shows no active
// port at all (not possible for a slave the frame reached) is taken as having
// its port 0 only. A slave found when no earlier slave has an unused port
// left hangs on the master (parent empty): the first slave, and in a ring
// broken for cable redundancy the slaves reached through the second master
// port (their place behind it is not reconstructed).
std::vector<SlaveTopology> compute_topology(std::span<const TopologyInput> slaves);

}  // namespace ecat::master
