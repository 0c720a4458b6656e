// Command line of ecat-slave (see --help and README.md).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "apps/ecat-slave/topology.hpp"
#include "slave/eoe_init_check.hpp"
#include "slave/frame_age.hpp"

namespace ecat::app {

// What a master may write into --state-dir (docs/security.md): FoE files and
// stored parameters of every slave together.
inline constexpr std::uint64_t kDefaultStateQuotaBytes = std::uint64_t{64} << 20;
inline constexpr std::uint64_t kDefaultStateMaxFiles = 1024;

struct SlaveProgramOptions {
  // Devices, in chain order. Empty: the embedded generic servo.
  std::vector<std::string> device_files;  // --device / --chain
  std::vector<std::string> esi_files;     // --esi
  std::optional<std::uint32_t> product_code;
  std::optional<std::uint32_t> revision;
  std::optional<std::string> type_name;   // --type: ESI device by its Type text
  std::string eni_file;                   // --eni: the chain of an ETG.2100 ENI
  std::string esi_dir;                    // --esi-dir: ESI files for the ENI's slaves
  bool strict = false;  // --strict: ESI import warnings are errors
  unsigned count = 1;                     // --count: copies of the (last) device

  // --topology: the slaves and their cables (docs/topology.md); its device
  // files are also in device_files, in slave order.
  std::optional<Topology> topology;
  // --redundant-iface: the master's second port, on the ring's far end
  // (the topology's `redundant` port, or the last slave's port 1).
  std::string redundant_iface;
  // --toggle-link NAME:PORT,...: SIGUSR2 cuts these cables, the next SIGUSR2
  // restores them (NAME from the topology, or the slave number 1.. of a chain).
  std::string toggle_links;
  // --corrupt-link NAME:PORT,...: each SIGUSR2 makes these cables corrupt
  // their next --corrupt-frames frames (bad FCS; --corrupt-rx-error: a
  // physical-layer RX error) - error counters 0x0300-0x030C (docs/topology.md).
  std::string corrupt_links;
  unsigned corrupt_frames = 1;
  bool corrupt_rx_error = false;

  // Exactly one medium.
  std::string iface;
  std::string pcap_in;
  std::string pcap_out;
  std::string udp;        // "PORT" (loopback only) or "ADDR:PORT" / "[V6ADDR]:PORT"
  std::string udp_allow;  // "CIDR[,CIDR...]": UDP sources served; empty: all
  // Or a real ESC on SPI: the firmware alone, over a LAN9252 / ET1100
  // (run_spi.cpp, docs/real-esc.md).
  std::string pdi;            // --pdi CHIP:SPIDEV
  std::uint32_t spi_hz = 10'000'000;
  unsigned spi_mode = 0;
  std::string irq_gpio;       // CHIP:OFFSET, e.g. /dev/gpiochip0:25
  bool lan9252_lean = false;  // FAST READ, one PRAM setup write, no CSR busy poll

  // --pdi-host PATH: the first slave's firmware is another process, attached
  // to its ESC's PDI over this Unix socket (docs/pdi-host.md); --pdi-chip:
  // the PDI it gets (direct, lan9252, et1100-spi).
  std::string pdi_host;
  std::string pdi_chip = "direct";

  // --control: the control interface (docs/control.md), a Unix socket path
  // or [ADDR:]PORT (TCP, 127.0.0.1 when only a port is given); empty: none.
  std::string control;
  // --http [ADDR:]PORT: the browser's view on the control interface
  // (docs/webview.md), 127.0.0.1 unless ADDR is named; --http-root DIR: its files.
  std::string http;
  std::string http_root;
  // --scenario FILE: steps run through the control interface, with a
  // pass/fail summary (docs/scenarios.md); --junit FILE writes it as JUnit XML.
  std::string scenario;
  std::string junit;

  // --eoe-ip A.B.C.D: start-up IP of the EoE slaves (the n-th EoE slave
  // of the chain gets A.B.C.D + n - 1, MAC 02:00:00:00:hi:lo of its
  // position); --eoe-tap NAME: the first EoE slave's Ethernet side is TAP
  // NAME instead of the built-in ARP/ping responder (docs/eoe.md).
  std::string eoe_ip;
  // --eni: per slave, the ENI's EoE InitCmds to check (filled by load_devices;
  // docs/eoe.md "ENI EoE InitCmds").
  std::vector<std::vector<slave::EoeInitExpectation>> eoe_init;
  std::string eoe_tap;
  std::string state_dir;  // stored parameters and FoE files
  // --foe-password N: FoE read/write requests must carry it (ERR 0x800A
  // otherwise); --foe-busy N: each is answered BUSY N times before it is
  // served (coe::FoeServer; docs/conformance.md FoE). Every slave of the chain.
  std::uint32_t foe_password = 0;
  std::uint16_t foe_busy = 0;
  std::uint64_t state_quota_bytes = kDefaultStateQuotaBytes;  // all files in state_dir together
  std::uint64_t state_max_files = kDefaultStateMaxFiles;
  double stats_seconds = 0;
  int rt_priority = 0;
  int cpu = -1;
  bool busy_poll = false;
  // --spin-us N: after each frame, look at the socket without sleeping for
  // N microseconds before the loop may sleep again (0: sleep at once).
  // --spin-us auto (the default): as long as the master's frames come in
  // bursts (slave/burst_spin.hpp).
  std::int64_t spin_us = 0;
  bool spin_auto = true;
  // --max-frame-age US: a frame taken from the socket more than this long
  // after the kernel stamped it is lost on the wire (slave/frame_age.hpp,
  // docs/e2e.md "Stale frames"); 0: never dropped.
  std::int64_t max_frame_age_us =
      std::chrono::duration_cast<std::chrono::microseconds>(slave::kDefaultMaxFrameAge).count();
  // --firmware-threads N: the slaves' firmware on N threads
  // (slave::Chain::set_firmware_threads); 1: the loop's thread alone.
  // --firmware-threads auto: 1 or 2 chosen from the host and the chain
  // (slave/lane_choice.hpp).
  unsigned firmware_threads = 1;
  bool firmware_threads_auto = false;
  // --firmware-threads-recheck S: with auto, a live run judges one thread
  // against two again every S seconds (slave/lane_judge.hpp); 0: the
  // start's choice stays.
  double firmware_threads_recheck_s = 10.0;
  std::string trace_vcd;
  std::string plot_svg;
  std::vector<double> ppm;  // per slave oscillator error
  bool keep_privileges = false;
  bool quiet = false;
};

}  // namespace ecat::app
