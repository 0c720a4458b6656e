// `ecat-slave --topology FILE`: which device hangs on which port of which
// slave (docs/topology.md). A small line format:
//
//   # comment
//   slave NAME FILE                      the first slave: its port 0 on the master
//   slave NAME FILE at PARENT:PORT       port 0 of NAME cabled to PORT of PARENT
//   slave NAME FILE at PARENT:PORT port N    ... with NAME's port N instead of 0
//   redundant NAME:PORT                  the master's second port (ring's far end)
//
// After the placement a slave line may add `cable NS` (the delay of the
// cable to its parent, ns; default esc::Segment::kDefaultHopDelay) and
// `inner P F` (the ESC's processing and forwarding delays, ns;
// docs/esc.md "Forwarding delays inside an ESC").
//
// Device FILE paths are relative to the topology file. Slaves are numbered
// in file order; a parent must come before its children.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/clock.hpp"
#include "common/expected.hpp"

namespace ecat::app {

struct TopologySlave {
  std::string name;
  std::string device_file;
  std::optional<std::size_t> parent;  // none: on the master's port 0
  unsigned parent_port = 0;
  unsigned port = 0;
  int line = 0;
  std::optional<Nanoseconds> cable;       // `cable NS`
  std::optional<Nanoseconds> processing;  // `inner P F`
  std::optional<Nanoseconds> forwarding;
};

// A cable named by slave and port, for --toggle-link and `redundant`.
struct SlavePort {
  std::size_t slave = 0;
  unsigned port = 0;
};

struct Topology {
  std::vector<TopologySlave> slaves;
  std::optional<SlavePort> redundant;
  std::optional<std::size_t> find(std::string_view name) const;
  // "NAME:PORT" with a known NAME and PORT 0..3.
  Expected<SlavePort, std::string> parse_port(std::string_view text) const;
};

// Errors name `source` and the line ("FILE:LINE: ...").
Expected<Topology, std::string> parse_topology(std::string_view text, const std::string& source,
                                               const std::string& base_dir);
Expected<Topology, std::string> load_topology(const std::string& path);

}  // namespace ecat::app
