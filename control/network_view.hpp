// The network as the control interface shows it (issue 26 item 1): the
// slaves in topology order with identity, name, AL state and status code,
// DL status per port, error counters, sync errors and watchdog state, read
// from the ESC registers and the firmware's counters without side effects
// (docs/control.md "network").
#pragma once

#include <cstddef>

#include <nlohmann/json.hpp>

namespace ecat::slave {
class Chain;
class VirtualSlave;
struct ChainStats;
class CycleTiming;
}  // namespace ecat::slave

namespace ecat::control {

nlohmann::json slave_view(const slave::VirtualSlave& slave, std::size_t position);
// Where a port's cable goes: {"slave": n, "port": p}, {"master": master port}
// or null (nothing cabled).
nlohmann::json peer_view(const slave::Chain& chain, std::size_t slave, unsigned port);
// slave_view with each port's "peer".
nlohmann::json slave_view(const slave::Chain& chain, std::size_t position);
// {"slaves": [slave_view...], "frames": frames_view}
nlohmann::json network_view(const slave::Chain& chain);
// The chain's frame counters: {"received", "returned", "malformed", "lost",
// "stale", "datagrams", "wkc_total"}.
// The chain's frame counters and the master's cycle (slave::CycleTiming,
// settled by the caller): cycles, the period and the lateness buckets.
nlohmann::json frames_view(const slave::ChainStats& stats, const slave::CycleTiming& cycles);

}  // namespace ecat::control
