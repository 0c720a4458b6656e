// ecat-master: a small EtherCAT master on the project's master library.
// Scans a segment, brings it to Op, exchanges process data cyclically and
// prints the cycle statistics; with --move it also enables and moves every
// CiA402 drive. Used by the end-to-end tests and the quick start; with
// --in-process it runs against virtual slaves in the same process.
#include <time.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <vector>
#include <memory>
#include <optional>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "apps/ecat-master/capture.hpp"
#include "apps/ecat-master/session.hpp"
#include "apps/ecat-slave/realtime.hpp"
#include "master/redundant_transport.hpp"
#include "esi/device_loader.hpp"
#include "slave/chain.hpp"
#include "transport/in_memory_transport.hpp"
#include "transport/pcap_file.hpp"
#include "transport/raw_socket_transport.hpp"
#include "transport/udp_transport.hpp"

namespace {

constexpr int kExitUsage = 2;
constexpr int kExitFailure = 1;

struct Options {
  std::string iface, udp;
  std::string redundant_iface;  // second master port of a ring (cable redundancy)
  bool in_process = false;
  std::vector<std::string> devices;
  unsigned count = 1;
  std::string record;
  std::vector<std::string> sdo_reads;  // --sdo-read INDEX:SUB (hex)
  std::string capture;  // --capture DIR
  double period_us = 1000;
  double dc_lead_us = -1;
  int rt_priority = 0;
  ecat::app::SessionOptions session;
};

constexpr std::int64_t kNsPerSecond = 1'000'000'000;
// Slaves one segment may hold: the largest --count; the process image of that
// many drives takes several frames per cycle (master/process_image_plan.hpp).
constexpr unsigned kMaxSlaves = 1024;

// Sleeps to an absolute CLOCK_MONOTONIC time (SteadyClock is steady_clock,
// CLOCK_MONOTONIC on Linux): a wake-up that comes late does not push the
// following deadlines, and a signal only resumes the same sleep.
void sleep_until(ecat::Nanoseconds deadline) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(deadline.count() / kNsPerSecond);
  ts.tv_nsec = static_cast<long>(deadline.count() % kNsPerSecond);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

// SIGINT or SIGTERM during the cyclic run end it at the next cycle, and the
// statistics are printed as after the last cycle (as ping does on Ctrl-C):
// a test that stops the master still gets its figures, lateness included.
// A second signal does the same (no SA_RESETHAND): `timeout` sends its
// SIGTERM to the program and again to its process group, and the second
// must not kill it before the report. Installed only for the cyclic run: a
// signal during the scan or the start-up ends the program as before.
volatile std::sig_atomic_t stop_requested = 0;
void on_stop_signal(int) { stop_requested = 1; }
void stop_on_signals() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

int report(const ecat::app::SessionReport& r, const Options& o) {
  std::printf("cycles %llu lost %llu wkc-errors %llu state-errors %llu rtt-median-us %.1f rtt-p99-us %.1f rtt-max-us %.1f "
              "cycle-jitter-max-us %.1f\n",
              static_cast<unsigned long long>(r.cycles), static_cast<unsigned long long>(r.lost_frames),
              static_cast<unsigned long long>(r.wkc_errors), static_cast<unsigned long long>(r.state_errors),
              static_cast<double>(r.rtt_median.count()) / 1e3,
              static_cast<double>(r.rtt_p99.count()) / 1e3, static_cast<double>(r.rtt_max.count()) / 1e3,
              static_cast<double>(r.jitter_max.count()) / 1e3);
  std::printf("lateness-us %s max %.1f skipped-periods %llu\n", r.lateness.to_string().c_str(),
              static_cast<double>(r.lateness.max().count()) / 1e3, static_cast<unsigned long long>(r.skipped_slots));
  if (r.phase_locked) {
    std::printf("dc-phase error-p99-us %.1f error-max-us %.1f margin-min-us %.1f sync0-without-frame %llu\n",
                static_cast<double>(r.phase_error_p99.count()) / 1e3,
                static_cast<double>(r.phase_error_max.count()) / 1e3, static_cast<double>(r.margin_min.count()) / 1e3,
                static_cast<unsigned long long>(r.sync0_without_frame));
  }
  for (std::size_t i = 0; i < r.left_op.size(); ++i) {
    if (r.left_op[i] != 0) {
      std::printf("slave %zu: left Op %u time(s), recovered; last AL status code 0x%04X\n", i + 1, r.left_op[i],
                  r.last_code[i]);
    }
  }
  for (std::size_t i = 0; i < r.reconnected.size(); ++i) {
    if (r.reconnected[i] != 0) {
      std::printf("slave %zu: came back fresh %u time(s), addressed and configured again (hot connect)\n", i + 1,
                  r.reconnected[i]);
    }
  }
  bool ok = r.lost_frames == 0 && r.wkc_errors == 0 && r.state_errors == 0;
  if (o.session.move && !r.moved_ok) {
    std::fprintf(stderr, "ecat-master: a drive did not follow the move\n");
    ok = false;
  }
  return ok ? 0 : kExitFailure;
}

// One line on the ring after the run: its last state, where it is broken,
// and how many exchanges found it in each state.
void report_ring(const ecat::master::RedundantTransport& ring, std::size_t slaves) {
  const auto& st = ring.stats();
  std::printf("redundancy: %s", std::string(ecat::master::describe(ring.state())).c_str());
  if (auto b = ring.ring_break(slaves)) {
    std::printf(" between slave %zu and slave %zu", b->last_primary_side + 1, b->first_secondary_side + 1);
  }
  std::printf(" (exchanges: intact %llu broken %llu primary-down %llu secondary-down %llu no-reply %llu)\n",
              static_cast<unsigned long long>(st.intact), static_cast<unsigned long long>(st.broken),
              static_cast<unsigned long long>(st.primary_down), static_cast<unsigned long long>(st.secondary_down),
              static_cast<unsigned long long>(st.no_reply));
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App cli{"ecat-master: scan an EtherCAT segment, bring it to Op and exchange process data"};
  cli.set_version_flag("--version", "ecat-master (ecatslave) " ECAT_VERSION);
  auto* iface = cli.add_option("--iface", o.iface, "Network interface of the segment (raw Ethernet)");
  auto* udp = cli.add_option("--udp", o.udp, "Slave(s) served as EtherCAT-in-UDP at ADDR[:PORT]");
  cli.add_option("--redundant-iface", o.redundant_iface,
                 "Second master port: the segment is a ring from --iface back to this interface (cable redundancy)")
      ->needs(iface);
  auto* inproc = cli.add_flag("--in-process", o.in_process, "Run against virtual slaves in this process");
  cli.add_option("--device", o.devices, "Device file of an in-process slave (repeat for a chain; default: generic servo)")
      ->check(CLI::ExistingFile);
  cli.add_option("--count", o.count, "In-process: number of slaves (copies of the last device)")->check(CLI::Range(1u, kMaxSlaves));
  cli.add_option("--cycles", o.session.cycles, "Cyclic exchanges to run");
  cli.add_option("--period-us", o.period_us, "Cycle period in microseconds")->check(CLI::Range(50.0, 1e6));
  cli.add_option("--expect-slaves", o.session.expect_slaves, "Fail unless the scan finds this many slaves");
  cli.add_flag("--topology", o.session.topology,
               "Print each slave's parent, the parent's port, active and entry ports (and DC delays with --dc)");
  cli.add_flag("--scan", o.session.scan_only,
               "Scan and print the topology only, change no state (with --dc: also measure and print the DC "
               "delays, writing only the DC delay/offset registers)");
  cli.add_flag("--dc", o.session.dc, "Set up distributed clocks and DC Sync0 mode (1C32h/1C33h = 2)");
  cli.add_flag("--move", o.session.move, "Enable every CiA402 drive and move it in CSP mode");
  cli.add_option("--move-distance", o.session.move_distance, "Move distance in increments");
  cli.add_option("--dc-lead-us", o.dc_lead_us,
                 "With --dc: send each cyclic frame to reach the reference clock this long before SYNC0, locked "
                 "to the DC system time (default half the period; 0: no phase lock)")
      ->check(CLI::Range(0.0, 1e6));
  cli.add_option("--sdo-read", o.sdo_reads,
                 "In PreOp, upload object INDEX:SUB (hex, e.g. 1018:01) from every CoE slave and print its bytes "
                 "(repeatable)");
  cli.add_flag("--recover", o.session.recover,
               "Acknowledge a slave that left Op with an error and request Op again (state checked every 100 cycles); a slave that came back fresh at its position (power cycle) is addressed and configured again (hot connect; not with --dc)");
  cli.add_option("--rt-priority", o.rt_priority, "Run with SCHED_FIFO at this priority and lock memory")
      ->check(CLI::Range(1, 99));
  cli.add_option("--capture", o.capture,
                 "Scan and write each slave's device file (dictionary through SDO information, uploaded values as "
                 "defaults; SII-only without it), SII image and the topology (for ecat-slave --topology) to this "
                 "directory, then exit. Writes only the scan's registers, SM0/SM1 and AL control (PreOp and back to "
                 "Init), no SDO download: docs/twins.md");
  cli.add_option("--record", o.record, "Write every frame the master sends to this pcap file");
  cli.add_flag("-q,--quiet", [&](std::int64_t) { o.session.verbose = false; }, "Print only the summary");
  iface->excludes(udp)->excludes(inproc);
  udp->excludes(inproc);
  try {
    cli.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return cli.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return cli.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "ecat-master: %s (see --help)\n", e.what());
    return kExitUsage;
  }
  if (o.iface.empty() && o.udp.empty() && !o.in_process) {
    std::fprintf(stderr, "ecat-master: choose one of --iface, --udp or --in-process (see --help)\n");
    return kExitUsage;
  }
  o.session.period = ecat::Nanoseconds{static_cast<std::int64_t>(o.period_us * 1e3)};
  for (const std::string& text : o.sdo_reads) {
    unsigned index = 0;
    unsigned sub = 0;
    char tail = 0;
    if (std::sscanf(text.c_str(), "%x:%x%c", &index, &sub, &tail) != 2 || index > 0xFFFF || sub > 0xFF) {
      std::fprintf(stderr, "ecat-master: --sdo-read %s: expected INDEX:SUB in hex, e.g. 1018:01\n", text.c_str());
      return kExitUsage;
    }
    o.session.sdo_reads.emplace_back(static_cast<std::uint16_t>(index), static_cast<std::uint8_t>(sub));
  }
  if (o.dc_lead_us >= 0) {
    if (o.dc_lead_us >= o.period_us) {
      std::fprintf(stderr, "ecat-master: --dc-lead-us must be below the period (see --help)\n");
      return kExitUsage;
    }
    o.session.dc_lead = ecat::Nanoseconds{static_cast<std::int64_t>(o.dc_lead_us * 1e3)};
  }
  if (o.rt_priority != 0) {
    // Asked for explicitly: a refusal is fatal (as in ecat-slave).
    if (auto ok = ecat::app::set_realtime_priority(o.rt_priority); !ok) {
      std::fprintf(stderr, "ecat-master: %s\n", ok.error().c_str());
      return kExitFailure;
    }
    auto locked = ecat::app::lock_memory();
    if (!locked) {
      std::fprintf(stderr, "ecat-master: %s\n", locked.error().c_str());
      return kExitFailure;
    }
    if (*locked == ecat::app::MemoryLock::CurrentOnly) {
      std::fprintf(stderr, "ecat-master: RLIMIT_MEMLOCK could not be raised: only the memory mapped now is locked\n");
    }
  }

  ecat::SteadyClock steady;
  ecat::ManualClock simulated;
  const ecat::Clock& clock = o.in_process ? static_cast<const ecat::Clock&>(simulated) : steady;
  std::unique_ptr<ecat::transport::Transport> medium;
  std::unique_ptr<ecat::slave::Chain> chain;
  std::unique_ptr<ecat::transport::Transport> secondary;
  std::unique_ptr<ecat::master::RedundantTransport> ring;

  if (o.in_process) {
    chain = std::make_unique<ecat::slave::Chain>(simulated);
    std::vector<ecat::od::DeviceDescription> devices;
    for (const auto& f : o.devices) {
      auto d = ecat::esi::load_device_file(f);
      if (!d) {
        std::fprintf(stderr, "ecat-master: %s\n", d.error().to_string().c_str());
        return kExitFailure;
      }
      devices.push_back(std::move(*d));
    }
    if (devices.empty()) {
      auto d = ecat::esi::load_default_device();
      if (!d) {
        std::fprintf(stderr, "ecat-master: %s\n", d.error().to_string().c_str());
        return kExitFailure;
      }
      devices.push_back(std::move(*d));
    }
    while (devices.size() < o.count) devices.push_back(devices.back());
    for (std::size_t i = 0; i < devices.size(); ++i) {
      ecat::slave::SlaveOptions so;
      so.name = fmt::format("slave-{}", i + 1);
      if (auto ok = chain->add(std::move(devices[i]), so); !ok) {
        std::fprintf(stderr, "ecat-master: slave %zu: %s\n", i + 1, ok.error().c_str());
        return kExitFailure;
      }
    }
    auto* line = chain.get();
    medium = std::make_unique<ecat::transport::InMemoryTransport>([line, &simulated](ecat::Bytes frame) {
      // A frame takes a few microseconds on the wire and through the line.
      simulated.advance(std::chrono::microseconds(5));
      (void)line->process_frame(frame, simulated.now());
    });
  } else if (!o.iface.empty()) {
    auto t = ecat::transport::RawSocketTransport::open(o.iface);
    if (!t) {
      std::fprintf(stderr, "ecat-master: cannot open %s: %s\n", o.iface.c_str(),
                   std::string(ecat::transport::describe(t.error())).c_str());
      return kExitFailure;
    }
    medium = std::make_unique<ecat::transport::RawSocketTransport>(std::move(*t));
    if (!o.redundant_iface.empty()) {
      auto t2 = ecat::transport::RawSocketTransport::open(o.redundant_iface);
      if (!t2) {
        std::fprintf(stderr, "ecat-master: cannot open %s: %s\n", o.redundant_iface.c_str(),
                     std::string(ecat::transport::describe(t2.error())).c_str());
        return kExitFailure;
      }
      secondary = std::make_unique<ecat::transport::RawSocketTransport>(std::move(*t2));
      ring = std::make_unique<ecat::master::RedundantTransport>(*medium, *secondary, clock);
    }
  } else {
    auto ep = ecat::transport::parse_udp_endpoint(o.udp);
    auto t = ep ? ecat::transport::UdpTransport::connect(*ep)
                : ecat::Expected<ecat::transport::UdpTransport, ecat::transport::TransportError>(
                      ecat::fail(ep.error()));
    if (!t) {
      std::fprintf(stderr, "ecat-master: --udp %s: %s\n", o.udp.c_str(),
                   std::string(ecat::transport::describe(t.error())).c_str());
      return kExitFailure;
    }
    medium = std::make_unique<ecat::transport::UdpTransport>(std::move(*t));
  }

  std::optional<ecat::transport::PcapWriter> writer;
  std::unique_ptr<ecat::transport::RecordingTransport> recorder;
  ecat::transport::Transport* used = ring ? static_cast<ecat::transport::Transport*>(ring.get()) : medium.get();
  if (!o.record.empty()) {
    auto w = ecat::transport::PcapWriter::create(o.record);
    if (!w) {
      std::fprintf(stderr, "ecat-master: %s: %s\n", o.record.c_str(),
                   std::string(ecat::transport::describe(w.error())).c_str());
      return kExitFailure;
    }
    writer.emplace(std::move(*w));
    recorder = std::make_unique<ecat::transport::RecordingTransport>(*used, *writer, clock);
    used = recorder.get();
  }

  ecat::master::MasterConfig master_config;
  master_config.max_slaves = kMaxSlaves;  // the library's default (64) is SOEM-sized
  ecat::master::Master master(*used, clock, master_config);
  auto wait = [&](ecat::Nanoseconds deadline) {
    if (o.in_process) {
      if (deadline > simulated.now()) simulated.set(deadline);
      (void)chain->poll(simulated.now());
    } else {
      sleep_until(deadline);
    }
  };
  if (!o.capture.empty()) {
    auto captured = ecat::app::capture_network(master, o.capture);
    if (!captured) {
      std::fprintf(stderr, "ecat-master: %s\n", captured.error().c_str());
      return kExitFailure;
    }
    std::printf("captured %zu slave(s) into %s, %zu note(s)\n", captured->slaves, o.capture.c_str(), captured->notes);
    return 0;
  }
  o.session.stop = &stop_requested;
  ecat::app::Session session(master, clock, wait, o.session);
  if (auto ok = session.bring_up(); !ok) {
    std::fprintf(stderr, "ecat-master: %s\n", ok.error().c_str());
    // How far apart the start-up's own cycles went out: a DC slave refuses
    // Op (001Ah) when they miss its SYNC0s (docs/e2e.md "Live timing under load").
    std::printf("start-up-cycle-gap-max-us %.1f\n", static_cast<double>(session.startup_gap_max().count()) / 1e3);
    return kExitFailure;
  }
  if (o.session.scan_only) {
    if (ring) report_ring(*ring, master.slave_count());
    return 0;
  }
  stop_on_signals();
  auto r = session.run();
  if (ring) report_ring(*ring, master.slave_count());
  if (!r) {
    std::fprintf(stderr, "ecat-master: %s\n", r.error().c_str());
    return kExitFailure;
  }
  if (r->stopped) {
    std::fprintf(stderr, "ecat-master: stopped by a signal after %llu of %llu cycles\n",
                 static_cast<unsigned long long>(r->cycles), static_cast<unsigned long long>(o.session.cycles));
  }
  return report(*r, o);
}
