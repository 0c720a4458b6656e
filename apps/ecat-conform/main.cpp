// ecat-conform: runs the conformance suite (master/conformance) against one
// slave - in-process from a device file, on a network interface, or over UDP -
// prints a table, optionally writes JUnit XML, exits non-zero on any failure.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>

#include "apps/ecat-conform/target.hpp"
#include "esi/device_loader.hpp"
#include "master/conformance/suite.hpp"
#include "master/master.hpp"
#include "pdi_spi/pdi_spec.hpp"
#include "transport/pcap_file.hpp"

namespace {

constexpr int kExitFailures = 1;
constexpr int kExitUsage = 2;
// The master cycle a DC-only device's SYNC0 is derived from (ecat-master's default period).
constexpr std::uint32_t kMasterCycleNs = 1'000'000;

}  // namespace

int main(int argc, char** argv) {
  using namespace ecat;
  CLI::App app{"ecat-conform: EtherCAT slave conformance tests over the ecatslave master"};
  app.set_version_flag("--version", "ecat-conform (ecatslave) " ECAT_VERSION);
  std::string device, iface, udp, junit, filter, pcap, pdi_name;
  std::size_t slave = 0;
  bool list = false;
  bool free_run = false;
  auto* g = app.add_option_group("target", "what to test (exactly one)");
  auto* device_option = g->add_option("--device", device, "device file: test a virtual slave in-process");
  g->add_option("--iface", iface, "network interface: test the slave(s) on this link (needs CAP_NET_RAW)");
  g->add_option("--udp", udp, "ADDR:PORT of a slave speaking EtherCAT in UDP (ETG.1000.4)");
  g->require_option(0, 1);
  app.add_option("--pdi", pdi_name,
                 "with --device: the firmware reaches the ESC over SPI to an emulated lan9252 or et1100-spi")
      ->needs(device_option);
  app.add_option("--junit", junit, "write JUnit XML to this file");
  app.add_option("--filter", filter, "run only tests whose name contains PATTERN (or matches a * ? glob); several patterns separated by commas");
  app.add_option("--slave", slave, "position of the slave to test (default 0)");
  app.add_option("--pcap", pcap, "record every frame to this pcap file");
  app.add_flag("--free-run", free_run,
               "with --device: run a device whose ESI offers only DC OpModes in free run anyway (default: DC Sync0)");
  std::optional<std::uint32_t> foe_password;
  std::optional<std::size_t> foe_capacity;
  std::string foe_denied;
  app.add_option("--foe-password", foe_password, "FoE: the password the device's files need (sent in every read/write request; runs foe.wrong_password)");
  app.add_option("--foe-denied", foe_denied, "FoE: a file name the device denies access to (runs foe.access_denied)");
  bool foe_busy = false;
  app.add_flag("--foe-busy", foe_busy, "FoE: the device answers read/write requests BUSY before it serves them (runs foe.busy_then_complete)");
  app.add_option("--foe-capacity", foe_capacity, "FoE: bytes the device can store (runs foe.write_disk_full with a longer file)");
  std::string esi_file;
  app.add_option("--esi", esi_file,
                 "device file the esi.* cases compare the slave with (default: the --device file; "
                 "with --iface/--udp it adds them)");
  app.add_flag("--list", list, "list the tests and the clauses they check, then exit");
  CLI11_PARSE(app, argc, argv);

  // The device file the esi.* cases compare with: --esi, else --device's own.
  std::optional<od::DeviceDescription> esi_description;
  if (const std::string& file = !esi_file.empty() ? esi_file : device; !file.empty()) {
    auto loaded = esi::load_device_file(file);
    if (!loaded) {
      fmt::print(stderr, "ecat-conform: {}\n", loaded.error().to_string());
      return kExitUsage;
    }
    esi_description = std::move(*loaded);
  }

  if (list) {
    auto cases = master::conformance::all_cases();
    if (esi_description) {
      auto extra = conform::device_file_cases(*esi_description);
      cases.insert(cases.end(), extra.begin(), extra.end());
    }
    for (const auto& c : cases) {
      if (master::conformance::matches_filter(c.name, filter)) fmt::print("{:<40} {}\n", c.name, c.clause);
    }
    return 0;
  }
  if (device.empty() && iface.empty() && udp.empty()) {
    fmt::print(stderr, "ecat-conform: give one of --device, --iface, --udp (see --help)\n");
    return kExitUsage;
  }

  slave::PdiKind pdi = slave::PdiKind::Direct;
  if (!pdi_name.empty()) {
    auto chip = pdi_spi::parse_spi_chip(pdi_name);
    if (!chip) {
      fmt::print(stderr, "ecat-conform: --pdi: {}\n", chip.error());
      return kExitUsage;
    }
    pdi = *chip == pdi_spi::SpiChip::Lan9252 ? slave::PdiKind::Lan9252 : slave::PdiKind::Et1100Spi;
  }

  try {
    // Output files are opened before the target: a raw socket target drops root
    // once its socket is open, and a file in a directory only root may write
    // could not be created after that (seen with --pcap in /tmp/kickcat).
    std::optional<transport::PcapWriter> writer;
    if (!pcap.empty()) {
      auto w = transport::PcapWriter::create(pcap);
      if (!w) {
        fmt::print(stderr, "ecat-conform: {}: cannot create\n", pcap);
        return kExitUsage;
      }
      writer.emplace(std::move(*w));
    }
    std::ofstream junit_out;
    if (!junit.empty()) {
      junit_out.open(junit);
      if (!junit_out) {
        fmt::print(stderr, "ecat-conform: {}: cannot create\n", junit);
        return kExitUsage;
      }
    }
    auto target = !device.empty() ? conform::make_in_process_target(device, pdi)
                  : !iface.empty() ? conform::make_raw_socket_target(iface)
                                   : conform::make_udp_target(udp);
    if (!target) {
      fmt::print(stderr, "ecat-conform: {}\n", target.error());
      return kExitUsage;
    }
    conform::Target& t = **target;
    transport::Transport* bus = &t.transport();
    std::optional<transport::RecordingTransport> recorder;
    if (writer) {
      recorder.emplace(*bus, *writer, t.clock());
      bus = &*recorder;
    }
    master::Master m(*bus, t.clock());
    master::conformance::SuiteOptions options;
    options.filter = filter;
    options.slave = slave;
    options.identity = t.identity();
    if (!options.identity && esi_description) {
      const auto& id = esi_description->identity;
      options.identity = master::conformance::ExpectedIdentity{id.vendor_id, id.product_code, id.revision};
    }
    options.wait = [&t](Nanoseconds d) { t.wait(d); };
    options.power_cycle = [&t]() { return t.power_cycle(); };
    options.foe_password = foe_password;
    options.foe_denied_file = foe_denied;
    options.foe_capacity = foe_capacity;
    options.foe_busy = foe_busy;
    fmt::print("ecat-conform: {}\n", t.description());
    std::vector<master::conformance::Case> extra;
    if (esi_description) extra = conform::device_file_cases(*esi_description);
    if (const od::DeviceDescription* d = t.device()) {
      if (!free_run) options.dc = conform::dc_only_mode(*d, kMasterCycleNs);
      if (options.dc) fmt::print("ecat-conform: DC Sync0 mode: {}\n", options.dc->why);
    }
    const auto reports = master::conformance::run_suite(m, options, extra);
    fmt::print("{}", master::conformance::format_table(reports));
    if (!junit.empty()) {
      junit_out << master::conformance::junit_xml(reports, "ecat-conform");
      junit_out.flush();
      if (!junit_out) {
        fmt::print(stderr, "ecat-conform: {}: cannot write\n", junit);
        return kExitUsage;
      }
    }
    return master::conformance::failures(reports) == 0 ? 0 : kExitFailures;
  } catch (const std::exception& e) {
    fmt::print(stderr, "ecat-conform: {}\n", e.what());
    return kExitUsage;
  }
}
