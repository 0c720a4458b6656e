#include <poll.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "apps/ecat-slave/chain_setup.hpp"
#include "apps/ecat-slave/control_setup.hpp"
#include "slave/eoe_tap.hpp"
#include "apps/ecat-slave/pdi_host_setup.hpp"
#include "scenario/junit_report.hpp"
#include "apps/ecat-slave/realtime.hpp"
#include "apps/ecat-slave/runners.hpp"
#include "common/frame.hpp"
#include "slave/burst_spin.hpp"
#include "slave/fault_catalogue.hpp"
#include "slave/faults/reply_faults.hpp"
#include "slave/lane_choice.hpp"
#include "transport/raw_socket_transport.hpp"
#include "transport/udp_transport.hpp"

namespace ecat::app {
namespace {

volatile std::sig_atomic_t g_stop = 0;
volatile std::sig_atomic_t g_print_stats = 0;
volatile std::sig_atomic_t g_toggle_links = 0;

void on_stop(int) { g_stop = 1; }
void on_stats(int) { g_print_stats = 1; }
void on_toggle(int) { g_toggle_links = 1; }

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_stop;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  sa.sa_handler = on_stats;
  sigaction(SIGUSR1, &sa, nullptr);
  sa.sa_handler = on_toggle;
  sigaction(SIGUSR2, &sa, nullptr);
}

// --toggle-link / --corrupt-link: the cables SIGUSR2 cuts and restores, or
// makes corrupt their next frames (docs/topology.md).
Expected<std::vector<SlavePort>, std::string> named_links(const SlaveProgramOptions& o, const std::string& text,
                                                          const char* option, std::size_t slaves) {
  std::vector<SlavePort> out;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string item = text.substr(start, comma - start);
    start = comma + 1;
    if (item.empty()) continue;
    if (o.topology) {
      auto p = o.topology->parse_port(item);
      if (!p) return fail(fmt::format("{} {}", option, p.error()));
      out.push_back(*p);
      continue;
    }
    // A chain: slave number 1.. and port.
    unsigned number = 0;
    unsigned port = 0;
    char tail = 0;
    if (std::sscanf(item.c_str(), "%u:%u%c", &number, &port, &tail) != 2 || number == 0 || number > slaves ||
        port > 3) {
      return fail(fmt::format("{} {}: expected SLAVE:PORT with SLAVE 1..{} and PORT 0..3", option, item, slaves));
    }
    out.push_back(SlavePort{number - 1, port});
  }
  return out;
}

// Longest wait for a frame, so signals and timers are seen promptly even
// when ppoll is not interrupted.
constexpr Nanoseconds kMaxWait = std::chrono::milliseconds(50);
// --firmware-threads auto: the round trip looked at before a trial of two
// threads - 256 trips (~25 us with the cores close), ended after 1 ms.
constexpr unsigned kTrialProbeTrips = 256;
constexpr Nanoseconds kTrialProbe = std::chrono::milliseconds(1);

struct Medium {
  std::unique_ptr<transport::Transport> transport;
  const transport::UdpTransport* udp = nullptr;  // for its drop counters
  // --redundant-iface: the second master port's interface and both sockets.
  std::unique_ptr<transport::RawSocketTransport> redundant;
  int fd = -1;
};

Expected<Medium, std::string> open_raw(const SlaveProgramOptions& o) {
  auto t = transport::RawSocketTransport::open(o.iface);
  if (!t) {
    return fail(fmt::format("cannot open raw socket on {}: {}", o.iface, transport::describe(t.error())));
  }
  auto owned = std::make_unique<transport::RawSocketTransport>(std::move(*t));
  std::unique_ptr<transport::RawSocketTransport> redundant;
  if (!o.redundant_iface.empty()) {
    auto r = transport::RawSocketTransport::open(o.redundant_iface);
    if (!r) {
      return fail(fmt::format("cannot open raw socket on {}: {}", o.redundant_iface, transport::describe(r.error())));
    }
    redundant = std::make_unique<transport::RawSocketTransport>(std::move(*r));
  }
  const int fd = owned->fd();
  if (!o.keep_privileges) {
    if (auto d = transport::drop_privileges(); !d) {
      return fail(fmt::format("cannot drop privileges: {}", transport::describe(d.error())));
    }
  }
  return Medium{std::move(owned), nullptr, std::move(redundant), fd};
}

// "--udp PORT" serves 127.0.0.1 and ::1 only; any other reach takes an
// explicit address, and is announced (EtherCAT-in-UDP has no
// authentication: whoever reaches the port is the master; docs/security.md).
Expected<Medium, std::string> open_udp(const SlaveProgramOptions& o) {
  transport::IpAllowList allow;
  if (!o.udp_allow.empty()) {
    auto a = transport::IpAllowList::parse(o.udp_allow);
    if (!a) return fail(fmt::format("--udp-allow: {}", a.error()));
    allow = std::move(*a);
  }
  Expected<transport::UdpTransport, transport::TransportError> t = fail(transport::TransportError::OpenFailed);
  const bool port_only = o.udp.find_first_not_of("0123456789") == std::string::npos;
  if (port_only) {
    auto ep = transport::parse_udp_endpoint("127.0.0.1:" + o.udp);
    if (!ep) return fail(fmt::format("--udp {}: {}", o.udp, transport::describe(ep.error())));
    t = transport::UdpTransport::bind_loopback(ep->port);
  } else {
    auto ep = transport::parse_udp_endpoint(o.udp);
    if (!ep) return fail(fmt::format("--udp {}: {}", o.udp, transport::describe(ep.error())));
    t = transport::UdpTransport::bind(*ep);
  }
  if (!t) return fail(fmt::format("cannot bind UDP {}: {}", o.udp, transport::describe(t.error())));
  t->set_allow_list(std::move(allow));
  if (!t->loopback_only()) {
    // One line, printed even with --quiet: it is the one thing to know.
    std::fprintf(stderr,
                 "ecat-slave: warning: UDP %s is reachable unauthenticated from %s: whoever reaches it is the "
                 "master (docs/security.md)\n",
                 o.udp.c_str(), o.udp_allow.empty() ? "every network routed to it" : o.udp_allow.c_str());
  }
  auto owned = std::make_unique<transport::UdpTransport>(std::move(*t));
  const transport::UdpTransport* udp = owned.get();
  return Medium{std::move(owned), udp, nullptr, -1};
}

// The descriptors a frame may come on: the raw socket, or the UDP sockets.
std::size_t medium_fds(const Medium& m, pollfd* out) {
  if (!m.udp) {
    out[0] = pollfd{m.fd, POLLIN, 0};
    return 1;
  }
  for (std::size_t i = 0; i < m.udp->socket_count(); ++i) out[i] = pollfd{m.udp->socket_fd(i), POLLIN, 0};
  return m.udp->socket_count();
}

Expected<Medium, std::string> open_medium(const SlaveProgramOptions& o) {
  return o.iface.empty() ? open_udp(o) : open_raw(o);
}

std::string format_udp_stats(const transport::UdpStats& s) {
  return fmt::format("udp accepted {} refused-source {} length-mismatch {} replies-refused {}\n",
                     s.datagrams_accepted, s.refused_source, s.length_mismatch, s.replies_refused);
}

// `spin`: the --spin-us line, after the chain's first.
void print_stats(const slave::Chain& line, const transport::UdpTransport* udp, const slave::LaneJudge* judge,
                 const std::string& spin) {
  std::string out = format_stats(line, judge);
  out.insert(std::min(out.find('\n') + 1, out.size()), spin);
  if (udp) out += format_udp_stats(udp->stats());
  std::fputs(out.c_str(), stderr);
}

// The replies the reply faults (delay_frames, duplicate_frames,
// replay_frames: docs/faults.md) hold or add, sent when their time has come,
// each on its master port. `buffer` is free again: the frame in it went out.
void send_held_replies(slave::FaultCatalogue& faults, Nanoseconds now, std::span<std::uint8_t> buffer,
                       transport::Transport& primary, transport::Transport* redundant, bool quiet) {
  while (const auto held = faults.take_reply(now, buffer)) {
    transport::Transport& out = held->master_port == 0 || redundant == nullptr ? primary : *redundant;
    if (auto s = out.send(buffer.first(held->length)); !s && !quiet) {
      std::fprintf(stderr, "ecat-slave: send failed: %s\n", std::string(transport::describe(s.error())).c_str());
    }
  }
}

// --firmware-threads auto, judged while running: one frame's firmware wall
// time (`busy`: the polls before the frame and the run after it) to the
// judge, whose way the chain then takes; a switch is said on stderr.
void judge_frame(slave::LaneJudge& judge, slave::Chain& line, Nanoseconds now, Nanoseconds busy,
                 std::uint64_t& splits_seen, bool quiet) {
  // Before a trial of two threads, the cores' round trip (a few hundred
  // trips, at most kTrialProbe): with the helper's CPU taken or the cores
  // far apart, a trial would stall the master's frames (measured beside a
  // CPU hog: frames of 26 ms) for nothing.
  if (!judge.split() && judge.trial_due(now)) {
    const Nanoseconds trip = slave::cache_line_round_trip(kTrialProbeTrips, 1, kTrialProbe);
    if (trip > slave::kMaxLaneRoundTrip) {
      judge.skip_trial(now, fmt::format("no trial of 2 threads: a cache line between the cores and back takes {} ns, "
                                        "more than {} ns",
                                        trip.count(), slave::kMaxLaneRoundTrip.count()));
    }
  }
  const bool split_ran = line.split_runs() != splits_seen;
  splits_seen = line.split_runs();
  const std::uint32_t switches = judge.switches();
  if (!judge.add(now, busy, split_ran)) return;
  line.pause_split(!judge.split());
  if (!quiet && judge.switches() != switches) {
    std::fprintf(stderr, "ecat-slave: --firmware-threads auto: %s\n", judge.last_trial()->reason.c_str());
  }
}

}  // namespace

int run_live(const SlaveProgramOptions& o, std::vector<od::DeviceDescription> devices) {
  SteadyClock clock;
  auto chain = make_chain(o, std::move(devices), clock);
  if (!chain) {
    std::fprintf(stderr, "ecat-slave: %s\n", chain.error().c_str());
    return 1;
  }
  // The firmware helpers take the loop's SCHED_FIFO priority (a helper
  // preempted by an ordinary task would stall the loop that waits for it)
  // but not its CPU: they start after the priority is set, before the pin.
  if (o.rt_priority > 0) {
    if (auto ok = set_realtime_priority(o.rt_priority); !ok) {
      std::fprintf(stderr, "ecat-slave: %s\n", ok.error().c_str());
      return 1;
    }
  }
  auto lanes = start_firmware_threads(**chain, o, &clock);
  if (!lanes) {
    std::fprintf(stderr, "ecat-slave: %s\n", lanes.error().c_str());
    return 1;
  }
  const std::unique_ptr<slave::LaneJudge> lane_judge = std::move(*lanes);
  Nanoseconds firmware_busy{0};  // for lane_judge: since the last frame's judge_frame
  std::uint64_t splits_seen = 0;
  if (o.cpu >= 0) {
    if (auto ok = pin_to_cpu(o.cpu); !ok) {
      std::fprintf(stderr, "ecat-slave: %s\n", ok.error().c_str());
      return 1;
    }
  }
  if (o.rt_priority > 0) {
    auto locked = lock_memory();
    if (!locked) {
      std::fprintf(stderr, "ecat-slave: %s\n", locked.error().c_str());
      return 1;
    }
    if (*locked == MemoryLock::CurrentOnly && !o.quiet) {
      std::fprintf(stderr, "ecat-slave: RLIMIT_MEMLOCK cannot be raised: only the memory mapped now is locked\n");
    }
  }
  // The JUnit report is opened before the raw socket drops root's privileges
  // (the report is written at the end, as a user who may not write there).
  std::ofstream junit_file;
  if (!o.junit.empty()) {
    junit_file.open(o.junit, std::ios::binary | std::ios::trunc);
    if (!junit_file) {
      std::fprintf(stderr, "ecat-slave: %s: cannot write the JUnit report\n", o.junit.c_str());
      return 1;
    }
  }
  // --eoe-tap: the TAP is created before the raw socket drops root's privileges.
  std::unique_ptr<slave::EoeTap> tap;
  std::size_t tap_slave = 0;
  if (!o.eoe_tap.empty()) {
    while (tap_slave < (*chain)->size() && !(**chain)[tap_slave].device().mailbox.eoe) ++tap_slave;
    if (tap_slave == (*chain)->size()) {
      std::fprintf(stderr, "ecat-slave: --eoe-tap: no slave's device lists EoE (Mailbox eoe=\"true\")\n");
      return 1;
    }
    auto opened = slave::EoeTap::open(o.eoe_tap, (**chain)[tap_slave].firmware().coe().eoe());
    if (!opened) {
      std::fprintf(stderr, "ecat-slave: %s\n", opened.error().c_str());
      return 1;
    }
    tap = std::move(*opened);
    if (!o.quiet) std::fprintf(stderr, "ecat-slave: slave %zu's EoE bridged to TAP %s\n", tap_slave + 1, tap->name().c_str());
  }
  auto medium = open_medium(o);
  if (!medium) {
    std::fprintf(stderr, "ecat-slave: %s\n", medium.error().c_str());
    return 1;
  }
  install_signal_handlers();
  if (!o.quiet) {
    const bool loopback = medium->udp && medium->udp->loopback_only();
    std::fprintf(stderr, "ecat-slave: %zu slave(s) on %s%s\n", (*chain)->size(),
                 o.iface.empty() ? ("udp " + o.udp).c_str() : o.iface.c_str(), loopback ? " (loopback only)" : "");
  }

  slave::Chain& line = **chain;
  line.set_max_frame_age(std::chrono::microseconds(o.max_frame_age_us));
  transport::Transport& t = *medium->transport;
  std::array<std::uint8_t, kMaxEthernetPayload + kEthernetHeaderSize + kVlanTagSize> buffer{};
  static_assert(sizeof buffer >= slave::faults::ReplyFaults::kMaxFrame, "a held reply fits the frame buffer");
  const Nanoseconds stats_period{static_cast<std::int64_t>(o.stats_seconds * 1e9)};
  Nanoseconds next_stats = clock.now() + stats_period;

  // Time moves on to the clock only when no frame waits: frames that queued
  // while the process was not scheduled are each processed at the time the
  // kernel stamped them, after the timers due before them (Chain::catch_up),
  // so a late wake-up does not reorder SYNC0 events and frames, and the DC
  // latches and watchdogs see when a frame arrived (docs/e2e.md "Live timing").
  auto toggled = named_links(o, o.toggle_links, "--toggle-link", line.size());
  if (!toggled) {
    std::fprintf(stderr, "ecat-slave: %s\n", toggled.error().c_str());
    return 1;
  }
  auto corrupted = named_links(o, o.corrupt_links, "--corrupt-link", line.size());
  if (!corrupted) {
    std::fprintf(stderr, "ecat-slave: %s\n", corrupted.error().c_str());
    return 1;
  }
  for (const SlavePort& p : *corrupted) {
    if (!line.segment().peer(p.slave, p.port)) {
      std::fprintf(stderr, "ecat-slave: --corrupt-link: nothing is cabled on port %u of slave %zu\n", p.port,
                   p.slave + 1);
      return 1;
    }
  }
  // SIGUSR2 engages and clears these as faults of the catalogue (docs/faults.md).
  slave::FaultCatalogue faults(line);
  // --control: serviced on its own tick below, off the frame path (docs/control.md).
  auto control = open_control(o, line, clock, faults);
  if (!control) {
    std::fprintf(stderr, "ecat-slave: %s\n", control.error().c_str());
    return 1;
  }
  // --pdi-host: the first slave's firmware in another process (docs/pdi-host.md).
  auto pdi_host = open_pdi_host(o, line, clock);
  if (!pdi_host) {
    std::fprintf(stderr, "ecat-slave: %s\n", pdi_host.error().c_str());
    return 1;
  }
  pdi_host::PdiHost* host = pdi_host->get();
  std::vector<slave::FaultId> cut;  // link_cut faults engaged by the last SIGUSR2
  std::vector<std::optional<slave::FaultId>> corrupting(corrupted->size());
  bool links_cut = false;
  unsigned next_port = 0;
  std::optional<Nanoseconds> deadline = line.poll(clock.now());
  bool drained = true;
  const Nanoseconds spin = std::chrono::microseconds(o.spin_us);
  slave::BurstSpin burst;     // --spin-us auto
  Nanoseconds spin_until{0};  // --spin-us: no sleep before this time
  const auto spin_line = [&] {
    return o.spin_auto ? fmt::format("spin-us auto {} (the last frame's)\n",
                                   std::chrono::duration_cast<std::chrono::microseconds>(burst.spin()).count())
                       : fmt::format("spin-us {}\n", o.spin_us);
  };
  while (!g_stop) {
    Nanoseconds wait = kMaxWait;
    if (!drained || o.busy_poll || clock.now() < spin_until) {
      wait = Nanoseconds{0};
    } else if (deadline) {
      wait = std::clamp(*deadline - clock.now(), Nanoseconds{0}, kMaxWait);
    }
    if (*control && (*control)->server) wait = std::min(wait, (*control)->server->until_due(clock.now()));
    if (*control && (*control)->web) wait = std::min(wait, (*control)->web->until_due(clock.now()));
    if (const auto due = faults.next_reply_due()) {  // delay_frames: a held reply's time
      wait = std::min(wait, std::max(*due - clock.now(), Nanoseconds{0}));
    }
    if (*control && (*control)->scenario) wait = std::min(wait, (*control)->scenario->until_due(clock.now()));
    if (host && host->busy()) wait = Nanoseconds{0};
    if (g_toggle_links) {
      g_toggle_links = 0;
      links_cut = !links_cut;
      if (links_cut) {
        for (const SlavePort& p : *toggled) {
          auto id = faults.engage({"link_cut", p.slave, p.port, {}});
          if (id) {
            cut.push_back(*id);
          } else if (!o.quiet) {
            std::fprintf(stderr, "ecat-slave: %s\n", id.error().c_str());
          }
        }
      } else {
        for (slave::FaultId id : cut) (void)faults.clear(id);
        cut.clear();
      }
      if (!o.quiet && !toggled->empty()) {
        std::fprintf(stderr, "ecat-slave: %zu link(s) %s\n", toggled->size(), links_cut ? "cut" : "restored");
      }
      for (std::size_t i = 0; i < corrupted->size(); ++i) {
        // A new signal starts the count again (a fault spent has cleared itself).
        if (corrupting[i]) (void)faults.clear(*corrupting[i]);
        corrupting[i].reset();
        if (o.corrupt_frames == 0) continue;
        const SlavePort& p = (*corrupted)[i];
        auto id = faults.engage({"corrupt_frames", p.slave, p.port,
                                 {{"count", o.corrupt_frames}, {"rx_error", o.corrupt_rx_error ? 1 : 0}}});
        if (id) {
          corrupting[i] = *id;
        } else if (!o.quiet) {
          std::fprintf(stderr, "ecat-slave: %s\n", id.error().c_str());
        }
      }
      if (!o.quiet && !corrupted->empty()) {
        std::fprintf(stderr, "ecat-slave: %zu link(s) corrupt their next %u frame(s)\n", corrupted->size(),
                     o.corrupt_frames);
      }
    }
    // With a redundant port: wait on both sockets, then take a frame from
    // the one that has it (the master port it arrived on).
    unsigned port = 0;
    bool host_ready = false;  // the firmware sent something or connects
    if (host && !medium->redundant) {
      // Frames or the firmware, whichever comes first.
      std::array<pollfd, transport::UdpTransport::kMaxSockets + kPdiHostFds> fds{};
      const std::size_t first_host = medium_fds(*medium, fds.data());
      const std::size_t n = first_host + host->fds(fds.data() + first_host, fds.size() - first_host);
      const timespec ts{static_cast<time_t>(wait.count() / 1'000'000'000), static_cast<long>(wait.count() % 1'000'000'000)};
      if (::ppoll(fds.data(), n, &ts, nullptr) > 0) {
        for (std::size_t i = first_host; i < n; ++i) host_ready |= fds[i].revents != 0;
      }
      wait = Nanoseconds{0};
    } else if (medium->redundant) {
      std::array<pollfd, esc::kMasterPorts + kPdiHostFds> fds{{{medium->fd, POLLIN, 0}, {medium->redundant->fd(), POLLIN, 0}}};
      const std::size_t n = esc::kMasterPorts + (host ? host->fds(fds.data() + esc::kMasterPorts, kPdiHostFds) : 0);
      const auto ms = static_cast<int>(std::chrono::duration_cast<std::chrono::milliseconds>(wait).count());
      if (::poll(fds.data(), n, ms) > 0) {
        for (std::size_t i = esc::kMasterPorts; i < n; ++i) host_ready |= fds[i].revents != 0;
        port = (fds[0].revents & POLLIN) != 0 ? 0 : 1;
        if ((fds[0].revents & POLLIN) != 0 && (fds[1].revents & POLLIN) != 0) port = next_port;
        next_port = 1 - next_port;  // both ready: take them in turn
      }
      wait = Nanoseconds{0};
    }
    // The firmware is answered between frames, not only when none waits:
    // a master polling back to back must not starve it.
    if (host && (host_ready || host->busy())) host->service(clock.now());
    transport::Transport& in = port == 0 ? t : *medium->redundant;
    auto r = in.receive_stamped(buffer, wait);
    if (r) {
      drained = false;  // look for the next queued frame before time moves on
      // A frame older than the master waits for is lost on the wire: not
      // passed, not answered, counted (Chain::admit, --max-frame-age).
      const Nanoseconds received = clock.now();
      if (o.spin_auto) burst.frame_arrived(r->arrival.value_or(received));
      const std::optional<Nanoseconds> admitted = line.admit(r->arrival, received);
      if (lane_judge) firmware_busy += clock.now() - received;  // the due polls before the frame
      if (!admitted) continue;
      const Nanoseconds at = *admitted;
      std::span<std::uint8_t> frame(buffer.data(), r->length);
      // The frame goes back as soon as the ESCs are done with it, on the
      // master port it comes out at; the firmware reacts afterwards, as a
      // µC behind a real ESC does.
      const esc::Delivery d = faults.pass_frame_on(frame, at, port);
      if (d.returned()) {
        transport::Transport& out = d.master_port == 0 ? t : *medium->redundant;
        if (auto s = out.send(frame); !s && !o.quiet) {
          std::fprintf(stderr, "ecat-slave: send failed: %s\n", std::string(transport::describe(s.error())).c_str());
        }
      }
      send_held_replies(faults, clock.now(), buffer, t, medium->redundant.get(), o.quiet);
      const Nanoseconds firmware_start = lane_judge ? clock.now() : Nanoseconds{0};
      line.run_firmware(at);
      if (lane_judge) {
        const Nanoseconds firmware_end = clock.now();
        judge_frame(*lane_judge, line, firmware_end, firmware_busy + (firmware_end - firmware_start), splits_seen,
                    o.quiet);
        firmware_busy = Nanoseconds{0};
      }
      if (host) host->notify(at);
      const Nanoseconds done = clock.now();
      spin_until = done + (o.spin_auto ? burst.frame_done(done) : spin);
      continue;
    }
    // A datagram dropped by policy (UDP source or length) is no error: time
    // moves on below, so a flood of refused datagrams cannot stall the timers.
    if (r.error() != transport::TransportError::Timeout && r.error() != transport::TransportError::BufferTooSmall &&
        r.error() != transport::TransportError::Dropped) {
      std::fprintf(stderr, "ecat-slave: receive failed: %s\n", std::string(transport::describe(r.error())).c_str());
      break;
    }
    drained = r.error() == transport::TransportError::Timeout;
    send_held_replies(faults, clock.now(), buffer, t, medium->redundant.get(), o.quiet);
    const Nanoseconds poll_start = clock.now();
    deadline = line.poll(poll_start);
    if (lane_judge) firmware_busy += clock.now() - poll_start;  // SYNC0's application cycles, watchdogs
    if (host) {
      host->notify(clock.now());  // SYNC pulses and events of the timers just run
      // The firmware's accesses may have armed a watchdog or changed events.
      deadline = line.poll(clock.now());
    }
    if (*control && (*control)->server) (*control)->server->service(clock.now());
    if (tap && tap->is_open()) {
      // Frames the host sent out of the TAP go to the master through the
      // next mailbox polls: the firmware looks at the next frame.
      if (tap->service() > 0) line[tap_slave].firmware().wake();
      if (!tap->is_open()) std::fprintf(stderr, "ecat-slave: --eoe-tap %s failed; EoE frames are dropped from now on\n", tap->name().c_str());
    }
    if (*control && (*control)->web) (*control)->web->service(clock.now());  // --http: one comparison between ticks
    if (*control && (*control)->scenario) {
      scenario::ScenarioRunner& run = *(*control)->scenario;
      run.poll(clock.now(), line.stats().frames_received);
      if (run.done()) break;
    }
    if (g_print_stats || (stats_period.count() > 0 && clock.now() >= next_stats)) {
      g_print_stats = 0;
      next_stats = clock.now() + stats_period;
      print_stats(line, medium->udp, lane_judge.get(), spin_line());
    }
  }
  int status = 0;
  if (auto ok = line.shutdown(); !ok) {
    std::fprintf(stderr, "ecat-slave: %s\n", ok.error().c_str());
    status = 1;
  }
  if (!o.plot_svg.empty()) {
    if (auto ok = line.write_plot(o.plot_svg); !ok) {
      std::fprintf(stderr, "ecat-slave: %s\n", ok.error().c_str());
      status = 1;
    }
  }
  if (!o.quiet) print_stats(line, medium->udp, lane_judge.get(), spin_line());
  if (*control && (*control)->scenario) {
    scenario::ScenarioRunner& run = *(*control)->scenario;
    run.abort(clock.now(), "ecat-slave was stopped before the scenario was over");
    // The summary is the scenario's verdict: printed even with --quiet.
    std::fputs(run.summary().c_str(), stderr);
    if (junit_file.is_open()) {
      junit_file << scenario::junit_xml(run);
      junit_file.close();
      if (!junit_file) {
        std::fprintf(stderr, "ecat-slave: %s: cannot write the JUnit report\n", o.junit.c_str());
        status = 1;
      }
    }
    if (status == 0 && !run.passed()) status = kExitScenarioFailed;
  }
  return status;
}

}  // namespace ecat::app
