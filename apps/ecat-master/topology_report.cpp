#include "apps/ecat-master/topology_report.hpp"

#include <fmt/format.h>

namespace ecat::app {

namespace {

std::string port_list(std::uint8_t ports) {
  std::string s;
  for (unsigned p = 0; p < master::kEscPortCount; ++p) {
    if ((ports & (1u << p)) == 0) continue;
    if (!s.empty()) s += ',';
    s += static_cast<char>('0' + p);
  }
  return s.empty() ? "-" : s;
}

}  // namespace

std::string topology_report(const master::Master& master, bool with_dc) {
  std::string out;
  for (std::size_t i = 0; i < master.slaves().size(); ++i) {
    const master::SlaveInfo& s = master.slaves()[i];
    const master::SlaveTopology& t = s.topology;
    out += fmt::format("slave {} station 0x{:04X} parent {} port {} ports {} entry {}", i + 1, s.station_address,
                       t.parent ? fmt::format("{}", *t.parent + 1) : std::string("master"), t.parent_port,
                       port_list(t.active_ports), t.entry_port);
    if (t.open_end_ports != 0) out += fmt::format(" open {}", port_list(t.open_end_ports));
    if (with_dc && s.esc.has_dc()) out += fmt::format(" delay {} ns", s.dc.delay_ns);
    out += '\n';
  }
  return out;
}

}  // namespace ecat::app
