// Command line of ecat-slave (see --help and README.md).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ecat::app {

struct SlaveProgramOptions {
  // Devices, in chain order. Empty: the embedded generic servo.
  std::vector<std::string> device_files;  // --device / --chain
  std::vector<std::string> esi_files;     // --esi
  std::optional<std::uint32_t> product_code;
  std::optional<std::uint32_t> revision;
  bool strict = false;  // --strict: ESI import warnings are errors
  unsigned count = 1;                     // --count: copies of the (last) device

  // Exactly one medium.
  std::string iface;
  std::string pcap_in;
  std::string pcap_out;
  std::string udp;  // "[ADDR:]PORT"

  std::string state_dir;  // stored parameters and FoE files
  double stats_seconds = 0;
  int rt_priority = 0;
  int cpu = -1;
  bool busy_poll = false;
  std::string trace_vcd;
  std::string plot_svg;
  std::vector<double> ppm;  // per slave oscillator error
  bool keep_privileges = false;
  bool quiet = false;
};

}  // namespace ecat::app
