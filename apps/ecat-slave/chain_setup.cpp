#include "apps/ecat-slave/chain_setup.hpp"

#include <arpa/inet.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

#include <fmt/format.h>

#include "common/huge_pages.hpp"
#include "slave/lane_choice.hpp"

namespace ecat::app {

Expected<std::unique_ptr<slave::Chain>, std::string> make_chain(const SlaveProgramOptions& options,
                                                               std::vector<od::DeviceDescription> devices,
                                                               const Clock& clock) {
  auto chain = std::make_unique<slave::Chain>(clock);
  // One budget for everything the slaves write into --state-dir (docs/security.md).
  std::shared_ptr<coe::StorageQuota> quota;
  if (!options.state_dir.empty()) {
    quota = std::make_shared<coe::StorageQuota>(
        coe::StorageQuota::Limits{options.state_quota_bytes, options.state_max_files});
    if (!quota->count_existing(options.state_dir)) {
      return fail(fmt::format("--state-dir {}: cannot read the directory", options.state_dir));
    }
  }
  std::uint32_t eoe_ip = 0;
  if (!options.eoe_ip.empty()) {
    in_addr a{};
    if (::inet_pton(AF_INET, options.eoe_ip.c_str(), &a) != 1) {
      return fail(fmt::format("--eoe-ip {}: not an IPv4 address (A.B.C.D)", options.eoe_ip));
    }
    eoe_ip = ntohl(a.s_addr);
  }
  std::uint32_t eoe_slaves = 0;
  for (std::size_t i = 0; i < devices.size(); ++i) {
    slave::SlaveOptions so;
    // EoE: a MAC of the slave's position, 02:00:00:00:hi:lo (locally
    // administered), and the next --eoe-ip address (docs/eoe.md).
    so.eoe.mac[4] = static_cast<std::uint8_t>((i + 1) >> 8);
    so.eoe.mac[5] = static_cast<std::uint8_t>(i + 1);
    if (eoe_ip != 0 && devices[i].mailbox.eoe) {
      so.eoe.ip = eoe_ip + eoe_slaves++;
      so.eoe.flags |= coe::eoe::kHasIp;
    }
    if (i < options.eoe_init.size() && !options.eoe_init[i].empty()) {
      so.eoe_init = options.eoe_init[i];
      so.report = [i](const std::string& line) { fmt::print(stderr, "ecat-slave: slave {}: {}\n", i + 1, line); };
    }
    so.state_dir = options.state_dir;
    so.state_quota = quota;
    so.foe_password = options.foe_password;
    so.foe_busy = options.foe_busy;
    so.name = fmt::format("slave-{}", i + 1);
    if (i < options.ppm.size()) so.clock_ppm = options.ppm[i];
    so.motion_trace = i == 0 && !options.plot_svg.empty();
    so.external_firmware = i == 0 && !options.pdi_host.empty();
    const TopologySlave* placed = options.topology && i < options.topology->slaves.size()
                                      ? &options.topology->slaves[i] : nullptr;
    if (placed) {
      so.name = placed->name;
      so.processing_delay = placed->processing;
      so.forwarding_delay = placed->forwarding;
    }
    auto ok = placed && placed->parent
                  ? chain->attach(std::move(devices[i]), so, *placed->parent, placed->parent_port, placed->port,
                                  placed->cable)
                  : chain->add(std::move(devices[i]), so);
    if (!ok) return fail(fmt::format("slave {}: {}", i + 1, ok.error()));
  }
  if (!options.redundant_iface.empty()) {
    // The ring's far end: the topology's `redundant` port, else the last slave's port 1.
    SlavePort end{chain->size() - 1, esc::kDownstreamPort};
    if (options.topology && options.topology->redundant) end = *options.topology->redundant;
    if (auto ok = chain->connect_redundant(end.slave, end.port); !ok) {
      return fail(fmt::format("--redundant-iface: {}", ok.error()));
    }
  }
  if (!options.trace_vcd.empty()) {
    if (auto ok = chain->open_trace(options.trace_vcd); !ok) return fail(ok.error());
  }
  // The built chain's heap on 2 MiB pages: at hundreds of slaves a cycle
  // otherwise walks page tables for thousands of 4 KiB pages
  // (common/huge_pages.hpp). Without them the run is only slower.
  if (auto advice = advise_heap_huge_pages(); !advice && !options.quiet) {
    fmt::print(stderr, "ecat-slave: {} (the heap stays on 4 KiB pages)\n", advice.error());
  }
  return chain;
}

Expected<std::unique_ptr<slave::LaneJudge>, std::string> start_firmware_threads(slave::Chain& chain,
                                                                                const SlaveProgramOptions& options,
                                                                                const Clock* judge_clock) {
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  const bool known = sched_getaffinity(0, sizeof allowed, &allowed) == 0;
  const unsigned cpus = known ? static_cast<unsigned>(CPU_COUNT(&allowed)) : 1u;
  unsigned threads = options.firmware_threads;
  std::unique_ptr<slave::LaneJudge> judge;
  if (options.firmware_threads_auto) {
    slave::LaneHost host;
    host.cpus = cpus;
    host.realtime = options.rt_priority > 0;
    host.slaves = chain.size();
    host.slaves_run_apart = chain.slaves_run_apart();
    const bool measured = slave::round_trip_decides(host);
    if (measured) host.round_trip = slave::cache_line_round_trip();
    const slave::LaneChoice choice = slave::choose_firmware_threads(host);
    threads = choice.threads;
    std::string again;
    if (measured && judge_clock != nullptr && options.firmware_threads_recheck_s > 0) {
      slave::LaneJudge::Settings s;
      s.every = std::chrono::duration_cast<Nanoseconds>(std::chrono::duration<double>(options.firmware_threads_recheck_s));
      judge = std::make_unique<slave::LaneJudge>(threads > 1, judge_clock->now(), s);
      again = fmt::format("; judged again every {} s while running", options.firmware_threads_recheck_s);
    }
    if (!options.quiet) {
      fmt::print(stderr, "ecat-slave: --firmware-threads auto: {} ({}){}\n", threads, choice.reason, again);
    }
  }
  // Judged: the helper is there for the trials of two threads, asleep while paused.
  const unsigned started = judge ? std::max(threads, 2u) : threads;
  if (auto ok = chain.set_firmware_threads(started); !ok) return fail(ok.error());
  if (judge && !judge->split()) chain.pause_split(true);
  if (known && threads > cpus && !options.quiet) {
    std::fprintf(stderr,
                 "ecat-slave: warning: --firmware-threads %u on %u CPU(s): the helpers spin between frames and "
                 "will take the loop's CPU time\n",
                 threads, cpus);
  }
  return judge;
}

std::string format_stats(const slave::Chain& chain, const slave::LaneJudge* judge) {
  const slave::ChainStats& s = chain.stats();
  std::string out = fmt::format(
      "frames {} returned {} malformed {} lost {} datagrams {} wkc-sum {} stale-dropped {}\n", s.frames_received,
      s.frames_returned, s.frames_malformed, s.frames_lost, s.datagrams, s.wkc_total, s.frames_stale);
  if (chain.firmware_threads() > 1) {
    // --firmware-threads: the firmware runs split over the threads, the
    // 64-slave words the helpers took, and whether something kept it serial.
    out += fmt::format("firmware-threads {} split-runs {} helper-words {}{}", chain.firmware_threads(),
                       chain.split_runs(), chain.helped_words(),
                       chain.firmware_kept_serial() ? " kept-serial (a fault's ESM guard)" : "");
    // --firmware-threads auto, judged while running: the way now, the
    // trials so far and the last one's verdict.
    if (judge) {
      out += fmt::format(" auto {} trials {} switches {}", chain.split_paused() ? "1" : "2", judge->trials(),
                         judge->switches());
      if (judge->last_trial()) out += fmt::format(" last: {}", judge->last_trial()->reason);
    }
    out += "\n";
  }
  for (std::size_t i = 0; i < chain.size(); ++i) {
    const slave::SlaveStatus st = chain[i].status();
    out += fmt::format("  slave {:>3} {:<24} {:<7}{} AL code 0x{:04X} ({}) cycles {} watchdog {} sync-errors {}\n",
                       i + 1, chain[i].device().identity.name, esc::describe(st.state),
                       st.error ? "+ERR" : "    ", static_cast<unsigned>(st.code), esc::describe(st.code),
                       st.application_cycles, st.watchdog_expiries, st.sync_errors);
  }
  return out;
}

}  // namespace ecat::app
