// DC propagation delays in a tree (docs/master.md "Topology and DC delays in trees").
#include "master/dc_delay.hpp"

namespace ecat::master {

namespace {

// 32-bit local times wrap (≈ 4.3 s): a difference is taken modulo 2^32.
std::int64_t elapsed(const PortTimes& t, unsigned from, unsigned to) noexcept {
  return static_cast<std::int32_t>(t[to] - t[from]);
}

}  // namespace

std::vector<std::optional<std::uint32_t>> compute_dc_delays(std::span<const SlaveTopology> topology,
                                                            std::span<const std::optional<PortTimes>> times) {
  const std::size_t n = topology.size() < times.size() ? topology.size() : times.size();
  std::vector<std::optional<std::uint32_t>> delay(n);
  std::vector<std::int64_t> exact(n, 0);
  for (std::size_t s = 0; s < n; ++s) {
    if (!times[s]) continue;
    // The nearest DC ancestor and the port of it whose branch holds s.
    std::size_t child = s;
    std::optional<std::size_t> ancestor = topology[s].parent;
    while (ancestor && (*ancestor >= n || !times[*ancestor])) {
      child = *ancestor;
      ancestor = topology[child].parent;
    }
    if (!ancestor) {  // the reference clock, or a DC slave with no DC slave before it
      delay[s] = 0;
      continue;
    }
    const std::size_t a = *ancestor;
    const SlaveTopology& at = topology[a];
    const PortTimes& ta = *times[a];
    const unsigned q = topology[child].parent_port;
    const unsigned before_q = previous_active_port(at.active_ports, q);
    // Time the frame spent in the ancestor's earlier branches (ports between
    // its entry port and q in processing order): a whole round trip each.
    const std::int64_t earlier = elapsed(ta, at.entry_port, before_q);
    // Round trip out of port q and back in on q: cables both ways plus
    // everything behind s.
    const std::int64_t round_trip = elapsed(ta, before_q, q);
    // The part of it spent behind s (s's own branches): from s's entry port
    // to the last port before it in processing order.
    const SlaveTopology& st = topology[s];
    const std::int64_t behind =
        elapsed(*times[s], st.entry_port, previous_active_port(st.active_ports, st.entry_port));
    const std::int64_t d = exact[a] + earlier + (round_trip - behind) / 2;
    exact[s] = d < 0 ? 0 : d;
    delay[s] = static_cast<std::uint32_t>(exact[s]);
  }
  return delay;
}

}  // namespace ecat::master
