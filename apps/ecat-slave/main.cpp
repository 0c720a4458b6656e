// ecat-slave: a virtual EtherCAT slave, or a chain of them, on a network
// interface (raw Ethernet), over UDP (ETG.1000.4 EtherCAT-in-UDP), or
// replaying a master's pcap capture. See README.md and --help.
#include <chrono>
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "apps/ecat-slave/device_list.hpp"
#include "apps/ecat-slave/options.hpp"
#include "apps/ecat-slave/runners.hpp"
#include "esi/esi_reader.hpp"
#include "slave/burst_spin.hpp"
#include "slave/chain.hpp"
#include "slave/lane_choice.hpp"

namespace {

constexpr int kExitUsage = 2;
constexpr int kExitFailure = 1;

std::vector<std::string> split_commas(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = text.find(',', start);
    const std::size_t end = comma == std::string::npos ? text.size() : comma;
    if (end > start) out.push_back(text.substr(start, end - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  using ecat::app::SlaveProgramOptions;
  SlaveProgramOptions o;
  std::string chain, product_code, revision, type_name, ppm, topology;

  CLI::App cli{
      "ecat-slave: virtual EtherCAT CoE slaves (a software ESC with mailbox, CoE and a CiA402 drive).\n"
      "With no device option it runs the embedded generic CiA402 servo."};
  cli.set_version_flag("--version", "ecat-slave (ecatslave) " ECAT_VERSION);
  cli.add_option("--device", o.device_files, "Device description (our XML format); repeat for a chain")
      ->check(CLI::ExistingFile);
  auto* esi = cli.add_option("--esi", o.esi_files,
                             "Vendor ESI file to emulate (first device, or --product-code/--revision/--type)")
                  ->check(CLI::ExistingFile);
  auto* pc = cli.add_option("--product-code", product_code, "Device of the ESI to emulate (#x hex or decimal)");
  auto* rev = cli.add_option("--revision", revision, "Revision of the ESI device to emulate (#x hex or decimal)");
  auto* type = cli.add_option("--type", type_name, "Device of the ESI to emulate by its type name (Type element)");
  auto* eni = cli.add_option("--eni", o.eni_file,
                             "ETG.2100 network description (ENI): the chain of its slaves, in its order")
                  ->check(CLI::ExistingFile);
  auto* esi_dir = cli.add_option("--esi-dir", o.esi_dir, "With --eni: directory of ESI files for the slaves' dictionaries")
                      ->check(CLI::ExistingDirectory);
  cli.add_flag("--strict", o.strict, "With --esi: every import warning (repair, element not modelled) is an error");
  cli.add_option("--chain", chain, "Comma-separated device files, in line order (port 0 -> port 1)");
  cli.add_option("--count", o.count, "Number of slaves: the listed devices, then copies of the last")
      ->check(CLI::Range(1u, 4096u));
  auto* topo = cli.add_option("--topology", topology,
                              "Slaves and cables of a tree or ring: which device hangs on which port of which "
                              "slave (docs/topology.md)")
                   ->check(CLI::ExistingFile);
  auto* iface = cli.add_option("--iface", o.iface, "Network interface to answer on (raw Ethernet, needs CAP_NET_RAW)");
  auto* red = cli.add_option("--redundant-iface", o.redundant_iface,
                             "Second interface, on the ring's far end (cable redundancy: the topology's 'redundant' "
                             "port, or the last slave's port 1)");
  cli.add_option("--toggle-link", o.toggle_links,
                 "NAME:PORT[,NAME:PORT...]: SIGUSR2 cuts these cables, the next SIGUSR2 restores them "
                 "(NAME from --topology, or the slave number 1.. of a chain)");
  cli.add_option("--corrupt-link", o.corrupt_links,
                 "NAME:PORT[,NAME:PORT...]: each SIGUSR2 makes these cables corrupt their next --corrupt-frames "
                 "frames (the ESCs count it in 0x0300-0x030C; the frame is lost to the master)");
  cli.add_option("--corrupt-frames", o.corrupt_frames, "Frames a --corrupt-link cable corrupts per SIGUSR2 (default 1)")
      ->check(CLI::Range(1u, 1000000u));
  cli.add_flag("--corrupt-rx-error", o.corrupt_rx_error,
               "--corrupt-link faults are physical-layer RX errors (also 0x0301+2n) instead of bad FCS");
  auto* pin = cli.add_option("--pcap-in", o.pcap_in, "Replay the master frames of this capture")->check(CLI::ExistingFile);
  auto* pout = cli.add_option("--pcap-out", o.pcap_out, "Write the frames as the segment returns them");
  auto* udp = cli.add_option("--udp", o.udp,
                             "Serve EtherCAT-in-UDP on PORT of 127.0.0.1 and ::1 only, or on ADDR:PORT "
                             "([V6ADDR]:PORT) - reachable unauthenticated from that network (port 34980 = 0x88A4)");
  auto* allow = cli.add_option("--udp-allow", o.udp_allow,
                               "Serve only UDP sources in these prefixes: CIDR[,CIDR...] (IPv4/IPv6); "
                               "others are dropped unanswered and counted");
  auto* pdi = cli.add_option("--pdi", o.pdi,
                             "Run the firmware on a real ESC: lan9252:/dev/spidevB.C or et1100-spi:/dev/spidevB.C "
                             "(its EEPROM written from ecat-esigen --sii of the same device file)");
  cli.add_option("--spi-hz", o.spi_hz, "SPI clock for --pdi (default 10000000)")->check(CLI::Range(1u, 100'000'000u));
  cli.add_option("--spi-mode", o.spi_mode, "SPI mode 0-3 for --pdi (default 0)")->check(CLI::Range(0u, 3u));
  cli.add_option("--irq-gpio", o.irq_gpio, "GPIO chip and line of the ESC's IRQ for --pdi (/dev/gpiochip0:25); "
                                           "without it the firmware polls");
  cli.add_flag("--lan9252-lean", o.lan9252_lean,
               "LAN9252: FAST READ, PRAM address+command in one write, CSR data read without polling "
               "(8 instead of 11 transactions per cycle; not confirmed on the data sheet, docs/real-esc.md)");
  auto* pdi_host = cli.add_option("--pdi-host", o.pdi_host,
                                  "The first slave's firmware is another process: its ESC's PDI is offered on this "
                                  "Unix socket PATH (mode 0600; docs/pdi-host.md, libecat_pdi, the SOES HAL)");
  auto* pdi_chip = cli.add_option("--pdi-chip", o.pdi_chip,
                                  "With --pdi-host: the PDI the firmware gets: direct (ESC memory reads/writes, "
                                  "default), lan9252 or et1100-spi (the chip's SPI transactions)")
                       ->check(CLI::IsMember({"direct", "lan9252", "et1100-spi"}));
  auto* control = cli.add_option("--control", o.control,
                                 "Control interface (docs/control.md, JSON lines): a Unix socket PATH (mode 0600), "
                                 "or [ADDR:]PORT for TCP (127.0.0.1 unless ADDR is named)");
  auto* http = cli.add_option("--http", o.http,
                              "Serve the browser's live view of the network (docs/webview.md) on [ADDR:]PORT "
                              "(127.0.0.1 unless ADDR is named; no authentication)");
  cli.add_option("--http-root", o.http_root,
                 "Directory of the page's files (default: $ECAT_WWW_DIR, else share/ecatslave/www next to the "
                 "program)")
      ->check(CLI::ExistingDirectory);
  auto* scenario = cli.add_option("--scenario", o.scenario,
                                  "Run this scenario file (YAML, docs/scenarios.md) against the masters: steps "
                                  "through the control interface, expectations on what the master does; ecat-slave "
                                  "exits when it is over, 0 if it passed, 3 if it failed")
                       ->check(CLI::ExistingFile);
  auto* junit = cli.add_option("--junit", o.junit, "With --scenario: write its result as JUnit XML to this file");
  cli.add_option("--eoe-ip", o.eoe_ip,
                 "Start-up IPv4 address of the EoE slaves (the next ones count up); the built-in responder answers "
                 "ARP and ping for it");
  cli.add_option("--eoe-tap", o.eoe_tap,
                 "Bridge the first EoE slave's Ethernet side to this Linux TAP interface (created if missing; "
                 "needs CAP_NET_ADMIN)");
  cli.add_option("--state-dir", o.state_dir, "Directory for stored parameters (1010h) and FoE files");
  cli.add_option("--foe-password", o.foe_password,
                 "FoE: password every file read/write request must carry (0x... or decimal; another one gets "
                 "ERR 0x800A no rights; default 0 = none)");
  cli.add_option("--foe-busy", o.foe_busy,
                 "FoE: answer each file read/write request BUSY this many times before serving it, as a slave "
                 "whose file is not ready at once (default 0)")
      ->check(CLI::Range(0, 0xFFFF));
  cli.add_option("--state-quota", o.state_quota_bytes,
                 "Most bytes all files in --state-dir may hold (FoE files + stored parameters; "
                 "suffixes k/M/G = 1024^n; default 64M)")
      ->transform(CLI::AsSizeValue(false));
  cli.add_option("--state-max-files", o.state_max_files, "Most files in --state-dir (default 1024)")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{1} << 20));
  cli.add_option("--stats", o.stats_seconds, "Print statistics every SECONDS (SIGUSR1 prints them once)")
      ->check(CLI::NonNegativeNumber);
  cli.add_option("--rt-priority", o.rt_priority, "Run with SCHED_FIFO at this priority and lock memory")
      ->check(CLI::Range(1, 99));
  cli.add_option("--cpu", o.cpu, "Pin the process to this CPU")->check(CLI::NonNegativeNumber);
  cli.add_flag("--busy-poll", o.busy_poll, "Poll the socket without sleeping (lowest latency, one core busy)");
  std::string spin_us = "auto";
  cli.add_option("--spin-us", spin_us,
                 fmt::format("After each frame, poll the socket without sleeping for this many microseconds before "
                             "the loop may sleep again: the next frames of the master's cycle find it awake (0: "
                             "sleep at once). auto (the default): while at least half of the last {0} frames came "
                             "within {1} us of the answer before (the master's cycle is a burst of frames), twice "
                             "the time three in four of those took, at most {1} us; else 0 (docs/e2e.md \"Frames "
                             "in bursts\")",
                             ecat::slave::BurstSpin::kHistory,
                             std::chrono::duration_cast<std::chrono::microseconds>(ecat::slave::BurstSpin::kBurstGap).count()))
      ->check(CLI::IsMember({"auto"}) | CLI::Range(std::int64_t{0}, std::int64_t{1'000'000}));
  cli.add_option("--max-frame-age", o.max_frame_age_us,
                 "A frame that waited in the socket longer than US microseconds (kernel receive stamp against "
                 "now) is lost on the wire: dropped unprocessed and counted (default 1000 = half of SOEM's frame "
                 "timeout; "
                 "0 = never; docs/e2e.md)")
      ->check(CLI::Range(std::int64_t{0}, std::int64_t{60'000'000}));
  std::string firmware_threads = "1";
  cli.add_option("--firmware-threads", firmware_threads,
                 fmt::format("Run the slaves' firmware on N threads: the loop's and N-1 helpers that spin between "
                             "frames (more CPU time for less wall time; the same frames as one thread; off with "
                             "--trace; default 1; docs/performance-log.md \"Firmware lanes\"). auto: 2 when the chain "
                             "has {} slaves or more, the process two CPUs (three with --rt-priority) and the cores "
                             "pass a cache line there and back in {} ns or less, else 1; the choice and why are "
                             "printed",
                             ecat::slave::Chain::kMinSplitSlaves, ecat::slave::kMaxLaneRoundTrip.count()))
      ->check(CLI::IsMember({"auto"}) | CLI::Range(1u, 64u));
  auto* recheck = cli.add_option("--firmware-threads-recheck", o.firmware_threads_recheck_s,
                 "With --firmware-threads auto in a live run: every SECONDS, run the firmware the other way "
                 "(1 or 2 threads) for half a second between two half seconds of the way in force, and take it "
                 "when it took at most 0.9x the wall time per frame; the statistics show each verdict (default "
                 "10; 0 = only the start's choice)")
      ->check(CLI::Range(0.0, 3600.0));
  cli.add_option("--ppm", ppm, "Comma-separated DC oscillator errors per slave in ppm (e.g. 100,-50)");
  auto* trace = cli.add_option("--trace", o.trace_vcd, "Write a VCD trace of SYNC pulses, SM events and ESM states");
  cli.add_option("--plot", o.plot_svg, "Write an SVG plot of the first drive's motion at exit");
  cli.add_flag("--keep-privileges", o.keep_privileges, "Do not drop root after opening the raw socket");
  cli.add_flag("-q,--quiet", o.quiet, "Print only errors");
  pc->needs(esi);
  rev->needs(esi);
  type->needs(esi);
  esi_dir->needs(eni);
  eni->excludes(esi);
  pin->needs(pout);
  pout->needs(pin);
  iface->excludes(pin)->excludes(udp);
  udp->excludes(pin);
  allow->needs(udp);
  pdi->excludes(iface)->excludes(pin)->excludes(udp);
  red->needs(iface);
  pdi_host->excludes(pin)->excludes(pdi);
  pdi_chip->needs(pdi_host);
  pdi_host->excludes(trace);  // both take the ESC's DC observer (SYNC pulses)
  control->excludes(pin)->excludes(pdi);
  http->excludes(pin)->excludes(pdi);
  scenario->excludes(pin)->excludes(pdi);
  junit->needs(scenario);
  topo->excludes(esi)->excludes(eni)->excludes(pdi);

  try {
    cli.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return cli.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return cli.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return cli.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "ecat-slave: %s (see --help)\n", e.what());
    return kExitUsage;
  }
  if (o.iface.empty() && o.pcap_in.empty() && o.udp.empty() && o.pdi.empty()) {
    std::fprintf(stderr, "ecat-slave: choose one of --iface, --pcap-in/--pcap-out, --udp or --pdi (see --help)\n");
    return kExitUsage;
  }
  if (spin_us != "auto") {
    o.spin_auto = false;
    o.spin_us = std::stoll(spin_us);  // checked: 0..1000000
  }
  if (firmware_threads == "auto") {
    o.firmware_threads_auto = true;
  } else {
    o.firmware_threads = static_cast<unsigned>(std::stoul(firmware_threads));  // checked: 1..64
  }
  if (recheck->count() > 0 && !o.firmware_threads_auto) {
    std::fprintf(stderr, "ecat-slave: --firmware-threads-recheck needs --firmware-threads auto (see --help)\n");
    return kExitUsage;
  }
  for (auto& f : split_commas(chain)) o.device_files.push_back(f);
  if (!topology.empty()) {
    if (!o.device_files.empty() || o.count != 1) {
      std::fprintf(stderr, "ecat-slave: --topology names every device; it takes no --device, --chain or --count\n");
      return kExitUsage;
    }
    auto t = ecat::app::load_topology(topology);
    if (!t) {
      std::fprintf(stderr, "ecat-slave: %s\n", t.error().c_str());
      return kExitFailure;
    }
    for (const auto& s : t->slaves) o.device_files.push_back(s.device_file);
    o.topology = std::move(*t);
  }
  if (!product_code.empty()) {
    o.product_code = ecat::esi::parse_esi_number(product_code);
    if (!o.product_code) {
      std::fprintf(stderr, "ecat-slave: --product-code: not a number: %s\n", product_code.c_str());
      return kExitUsage;
    }
  }
  if (!revision.empty()) {
    o.revision = ecat::esi::parse_esi_number(revision);
    if (!o.revision) {
      std::fprintf(stderr, "ecat-slave: --revision: not a number: %s\n", revision.c_str());
      return kExitUsage;
    }
  }
  if (!type_name.empty()) o.type_name = type_name;
  if (!o.eni_file.empty() && (!o.device_files.empty() || !o.esi_files.empty())) {
    std::fprintf(stderr, "ecat-slave: --eni gives the whole chain; it takes no --device, --chain or --esi\n");
    return kExitUsage;
  }
  for (auto& p : split_commas(ppm)) {
    try {
      o.ppm.push_back(std::stod(p));
    } catch (const std::exception&) {
      std::fprintf(stderr, "ecat-slave: --ppm: not a number: %s\n", p.c_str());
      return kExitUsage;
    }
  }

  auto devices = ecat::app::load_devices(o);
  if (!devices) {
    std::fprintf(stderr, "ecat-slave: %s\n", devices.error().c_str());
    return kExitFailure;
  }
  if (!o.pcap_in.empty()) return ecat::app::run_pcap(o, std::move(*devices));
  if (!o.pdi.empty()) return ecat::app::run_spi(o, std::move(*devices));
  return ecat::app::run_live(o, std::move(*devices));
}
