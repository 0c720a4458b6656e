// Propagation delays from the reference clock to every DC slave of a tree
// (ETG.1000.4 DC "propagation delay measurement", ETG.1020 §DC set-up; the
// same terms as SOEM's ecx_configdc: round trip behind the parent's port,
// minus the child's own round trip, halved, plus the time the frame spent
// in the parent's earlier branches). Pure function over the topology and the
// latched port times; docs/master.md "Topology and DC delays in trees".
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "master/topology.hpp"

namespace ecat::master {

// `times[i]` holds slave i's port receive times when it is a DC slave (0x0008
// bit 2) and was latched, empty otherwise. The first DC slave is the reference
// clock (delay 0). Returns per slave the delay in ns to write to 0x0928, empty
// for slaves without DC. Assumes, as every master does, that a cable and an
// ESC forward as fast as they return. Non-DC slaves between a DC slave and its
// nearest DC ancestor count as cable (exact when they forward on two ports).
std::vector<std::optional<std::uint32_t>> compute_dc_delays(std::span<const SlaveTopology> topology,
                                                            std::span<const std::optional<PortTimes>> times);

}  // namespace ecat::master
