// A chain that polls only the slaves whose time came (slave::Chain::
// set_polling_due, the default: docs/e2e.md "Live timing") against the same
// chain polling every slave before every frame and at every deadline, as
// ecat-slave runs it (Chain::catch_up, pass_frame, run_firmware; Chain::poll
// when the wire is quiet, at the deadline it returned). The project's master
// takes 18 generic servos through scan, SII, mailbox, DC with SYNC0 at
// 1 ms, SafeOp and Op, cycles with drift compensation and SDO uploads (and,
// made through the ESC from outside the chain, a step of one slave's local
// time and a LATCH0 pulse on another), cuts the line behind slave 3 until
// the slaves behind it leave Op (DC sync error 0x001A) and their
// process-data watchdogs expire, plugs it back, then sends nothing until
// every slave has left Op and every watchdog has expired. Every returned
// frame, every deadline poll() returned, every AL status change and SYNC
// edge with its time, and at the end every ESC's memory, DC registers,
// timers and firmware counters are the same.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

#include "common/le.hpp"
#include "esc/access_side.hpp"
#include "esc/dc/dc_unit.hpp"
#include "esc/registers.hpp"
#include "esc/dc/dc_registers.hpp"
#include "master/coe_client.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

using std::chrono::milliseconds;

// A line long enough to skip (esc::Segment::kSkipFrom) and for the chain to
// keep its slaves' wake times (slave::Chain::kTrackFrom).
constexpr std::size_t kSlaves = slave::Chain::kTrackFrom + 2;
constexpr std::size_t kCutAfter = 3;  // slaves 4 and on lose the line
constexpr std::size_t kJumped = 2;    // its local time steps
constexpr std::size_t kLatched = 1;   // its LATCH0 input toggles
constexpr std::uint16_t kLatch0Control = 0x09A8;
constexpr std::uint16_t kLatch0Status = 0x09AE;
constexpr std::uint16_t kLatch0TimePositive = 0x09B0;  // 8 bytes, then the negative edge's
constexpr std::int64_t kJump = 300'000;  // ns forward: SYNC0 comes 300 µs early once
constexpr Nanoseconds kCycle = milliseconds(1);
constexpr std::uint32_t kCycleNs = 1'000'000;
constexpr std::uint16_t kSyncModeDcSync0 = 2;
constexpr std::uint16_t kSmOutputParameter = 0x1C32;
constexpr std::uint16_t kSmInputParameter = 0x1C33;
constexpr std::uint8_t kSmEventMissed = 0x0B;
constexpr std::uint16_t kStartTimeCyclic = 0x0990;
constexpr Nanoseconds kLead = std::chrono::microseconds(500);
constexpr int kMaxPollsPerWait = 100'000;

struct SyncEdge {
  std::size_t slave;
  unsigned signal;
  bool level;
  Nanoseconds t;
  bool operator==(const SyncEdge&) const = default;
};
struct AlChange {
  std::size_t slave;
  Nanoseconds t;
  std::uint8_t status;
  std::uint16_t code;
  bool operator==(const AlChange&) const = default;
};

class SyncLog : public esc::DcObserver {
 public:
  SyncLog(std::vector<SyncEdge>& log, std::size_t slave) : log_(log), slave_(slave) {}
  void on_sync(unsigned signal, bool level, Nanoseconds t) noexcept override {
    log_.push_back({slave_, signal, level, t});
  }

 private:
  std::vector<SyncEdge>& log_;
  std::size_t slave_;
};

// kSlaves servos (or `n`) behind a live-style loop, every frame and event recorded.
struct LiveRig : InProcess {
  explicit LiveRig(bool due, std::size_t n = kSlaves) : n_(n), cut_after_(std::min(kCutAfter, n - 2)) {
    chain.set_polling_due(due);
    add_default(n_);
    for (std::size_t i = 0; i < n_; ++i) {
      sync_logs.emplace_back(std::make_unique<SyncLog>(sync, i));
      chain[i].esc().dc().set_observer(sync_logs.back().get());
    }
    seen_.resize(n_);
    wire.set_processor([this](Bytes frame) {
      clock.advance(kWireTime);
      const Nanoseconds at = chain.catch_up(clock.now(), clock.now());
      const bool returned = chain.pass_frame(frame, at);
      chain.run_firmware(at);
      if (!returned) wire.drop_next(1);
      frames.emplace_back(frame.begin(), frame.end());
      times.push_back(at);
      sample(at);
    });
  }

  // AL status changes as the master would read them, without touching the chain.
  void sample(Nanoseconds t) {
    const slave::Chain& c = chain;
    for (std::size_t i = 0; i < n_; ++i) {
      const std::uint8_t* m = c[i].esc().memory();
      const AlChange now{i, t, m[esc::reg::kAlStatus], load_le<std::uint16_t>(m + esc::reg::kAlStatusCode)};
      if (!seen_[i] || seen_[i]->status != now.status || seen_[i]->code != now.code) {
        al.push_back(now);
        seen_[i] = now;
      }
    }
  }

  // The slaves a poll at `t` left alone (their latest access is older).
  void count_unpolled(Nanoseconds t) {
    const slave::Chain& c = chain;
    for (std::size_t i = 0; i < n_; ++i) unpolled += c[i].esc().last_time() < t ? 1 : 0;
  }

  // Time passes with no frame: the chain is polled at every deadline it
  // returns, as ecat-slave's loop waits for it, up to `end`.
  void wait_until(Nanoseconds end) {
    for (int k = 0; k < kMaxPollsPerWait; ++k) {
      const std::optional<Nanoseconds> next = chain.poll(clock.now());
      deadlines.push_back(next);
      sample(clock.now());
      count_unpolled(clock.now());
      if (!next || *next > end) break;
      clock.set(std::max(*next, clock.now()));
    }
    if (clock.now() < end) {
      clock.set(end);
      deadlines.push_back(chain.poll(end));
      sample(end);
    }
  }

  std::string bring_up_dc() {
    auto n = master.scan();
    if (!n || *n != n_) return "scan";
    for (std::size_t i = 0; i < n_; ++i) {
      if (!master.configure_mailbox(i)) return "mailbox";
      auto st = master.request_state(i, master::AlState::PreOp);
      if (!st || st->error()) return "preop";
      master::CoeClient coe(master, i);
      for (std::uint16_t obj : {kSmOutputParameter, kSmInputParameter}) {
        if (!coe.download_value(obj, 1, kSyncModeDcSync0, 2)) return "sync mode";
      }
      if (!coe.read_pdo_sizes()) return "pdo sizes";
    }
    if (!master.configure_process_data()) return "process data";
    if (!master.configure_dc(clock.now())) return "dc";
    if (!master.dc_static_drift_compensation(20)) return "drift compensation";
    for (std::size_t i = 0; i < n_; ++i) {
      if (!master.configure_sync0(i, kCycleNs, 0, milliseconds(5))) return "sync0";
    }
    const slave::Chain& c = chain;
    const esc::Esc& first = c[0].esc();
    std::array<std::uint8_t, 8> start{};
    // 0x0990 of slave 0 through the master (a register read is a frame too).
    auto v = master.fprd_u32(master.slave(0).station_address, kStartTimeCyclic);
    if (!v) return "start time";
    auto hi = master.fprd_u32(master.slave(0).station_address, kStartTimeCyclic + 4);
    if (!hi) return "start time";
    store_le(start.data(), static_cast<std::uint64_t>(*v) | (static_cast<std::uint64_t>(*hi) << 32));
    const Nanoseconds pulse = first.dc().when_system(load_le<std::uint64_t>(start.data()));
    const Nanoseconds until = (pulse - clock.now()) % kCycle;
    next_ = clock.now() + (until - kLead + kCycle) % kCycle - kCycle;
    for (std::size_t i = 0; i < n_; ++i) {
      auto st = master.request_state(i, master::AlState::SafeOp);
      if (!st || st->error()) return "safeop";
    }
    for (int k = 0; k < 20; ++k) (void)tick();
    for (std::size_t i = 0; i < n_; ++i) {
      auto st = master.request_state(i, master::AlState::Op);
      if (!st || st->error()) return "op";
    }
    return "";
  }
  // One cycle on a fixed schedule: the deadlines up to the send time, then
  // the exchange (with the master's FRMW 0x0910).
  bool tick() {
    next_ += kCycle;
    wait_until(std::max(next_, clock.now()));
    return master.exchange_process_data().has_value();
  }
  // The missed SM events of every slave the line reaches (mailbox traffic).
  void upload_all(std::size_t reached) {
    for (std::size_t i = 0; i < reached; ++i) {
      master::CoeClient coe(master, i);
      uploads.push_back(coe.upload_value(kSmOutputParameter, kSmEventMissed).value_or(0xFFFF'FFFF));
    }
  }

  // The scripted run.
  void run() {
    // Held from set-up, as a PDI host holds its ESC: what it does later is
    // seen only through the ESC (its accesses mark it for the segment).
    esc::Esc& outside = chain[kJumped].esc();
    esc::Esc& latch_pin = chain[kLatched].esc();
    ASSERT_EQ(bring_up_dc(), "");
    const std::uint16_t latched = master.slave(kLatched).station_address;
    ASSERT_TRUE(master.fpwr_u8(latched, kLatch0Control, 0));  // continuous, both edges, ECAT-owned
    for (int k = 0; k < 200; ++k) {
      (void)tick();
      if (k % 50 == 0) upload_all(n_);
      // The local clock of one slave steps (a dc_time_jump without the
      // catalogue): its SYNC0 deadline moves earlier, then the time loop pulls it back.
      if (k == 100) outside.dc().jump_local_time(clock.now(), kJump);
      // LATCH0 of another goes high and low between frames: ECAT event
      // 0x0210 bit 0 in the IRQ field of the frames after, the times read back.
      if (k == 150) latch_pin.dc().set_latch_input(0, true, clock.now() - kLead);
      if (k == 160) latch_pin.dc().set_latch_input(0, false, clock.now() - kLead);
      if (k == 170) {
        std::array<std::uint8_t, 16> edges{};
        (void)master.fprd(latched, kLatch0TimePositive, edges);
        uploads.push_back(load_le<std::uint32_t>(edges.data()));
        uploads.push_back(load_le<std::uint32_t>(edges.data() + 8));
        uploads.push_back(master.fprd_u8(latched, kLatch0Status).value_or(0xFF));
      }
    }
    // The line cut behind slave cut_after_: the master cycles on, the
    // slaves behind the cut see no frame and expire.
    (void)chain.segment().set_link(cut_after_, esc::kDownstreamPort, false);
    for (int k = 0; k < 150; ++k) {
      (void)tick();
      if (k % 50 == 0) upload_all(cut_after_ + 1);
    }
    (void)chain.segment().set_link(cut_after_, esc::kDownstreamPort, true);
    for (int k = 0; k < 30; ++k) (void)tick();
    // No frame at all: every process-data watchdog expires.
    wait_until(clock.now() + milliseconds(150));
    for (int k = 0; k < 5; ++k) (void)tick();
    upload_all(n_);
  }

  std::size_t n_;
  std::size_t cut_after_;  // the slave behind which the line is cut
  std::vector<std::unique_ptr<SyncLog>> sync_logs;
  std::vector<std::vector<std::uint8_t>> frames;
  std::vector<Nanoseconds> times;
  std::vector<std::optional<Nanoseconds>> deadlines;
  std::vector<SyncEdge> sync;
  std::vector<AlChange> al;
  std::vector<std::uint32_t> uploads;
  std::size_t unpolled = 0;
  std::vector<std::optional<AlChange>> seen_;
  Nanoseconds next_{0};
};

// Both runs alike: frames, times, deadlines, events, uploads, and every
// slave's memory, timers, status and DC registers at the end.
void expect_same_run(LiveRig& due, LiveRig& all) {
  const std::size_t n = due.n_;
  ASSERT_EQ(due.frames.size(), all.frames.size());
  EXPECT_GT(due.frames.size(), 1000u);
  for (std::size_t k = 0; k < due.frames.size(); ++k) {
    ASSERT_EQ(due.frames[k], all.frames[k]) << "frame " << k;
    ASSERT_EQ(due.times[k], all.times[k]) << "frame " << k;
  }
  ASSERT_EQ(due.deadlines.size(), all.deadlines.size());
  for (std::size_t k = 0; k < due.deadlines.size(); ++k) ASSERT_EQ(due.deadlines[k], all.deadlines[k]) << "poll " << k;
  ASSERT_EQ(due.sync.size(), all.sync.size());
  for (std::size_t k = 0; k < due.sync.size(); ++k) ASSERT_EQ(due.sync[k], all.sync[k]) << "SYNC edge " << k;
  ASSERT_EQ(due.al.size(), all.al.size());
  for (std::size_t k = 0; k < due.al.size(); ++k) ASSERT_EQ(due.al[k], all.al[k]) << "AL change " << k;
  EXPECT_EQ(due.uploads, all.uploads);

  const slave::Chain& x = due.chain;
  const slave::Chain& y = all.chain;
  const Nanoseconds end = due.clock.now();
  ASSERT_EQ(end, all.clock.now());
  for (std::size_t i = 0; i < n; ++i) {
    const esc::Esc& a = x[i].esc();
    const esc::Esc& b = y[i].esc();
    ASSERT_EQ(a.memory_size(), b.memory_size());
    EXPECT_EQ(std::memcmp(a.memory(), b.memory(), a.memory_size()), 0) << "slave " << i;
    EXPECT_EQ(a.next_timer(), b.next_timer()) << "slave " << i;
    EXPECT_EQ(a.wake_bound(), b.wake_bound()) << "slave " << i;
    EXPECT_EQ(a.dc().system_time(end), b.dc().system_time(end)) << "slave " << i;
    const slave::SlaveStatus s = x[i].status();
    const slave::SlaveStatus t = y[i].status();
    EXPECT_EQ(s.state, t.state) << "slave " << i;
    EXPECT_EQ(s.code, t.code) << "slave " << i;
    EXPECT_EQ(s.application_cycles, t.application_cycles) << "slave " << i;
    EXPECT_EQ(s.firmware_polls, t.firmware_polls) << "slave " << i;
    EXPECT_EQ(s.watchdog_expiries, t.watchdog_expiries) << "slave " << i;
    EXPECT_GE(t.watchdog_expiries, 1u) << "slave " << i;
  }
  // The DC registers (0x0900-0x09FF) as the PDI reads them, both at the end.
  for (std::size_t i = 0; i < n; ++i) {
    std::array<std::uint8_t, esc::DcUnit::kSize> a{};
    std::array<std::uint8_t, esc::DcUnit::kSize> b{};
    due.chain[i].esc().dc().read(0, a, end, esc::Side::Pdi);
    all.chain[i].esc().dc().read(0, b, end, esc::Side::Pdi);
    EXPECT_EQ(a, b) << "slave " << i;
  }
}

TEST(ChainPoll, DuePollingGivesTheSameFramesEventsAndRegistersAsPollingEverySlave) {
  LiveRig due(true);
  LiveRig all(false);
  due.run();
  all.run();
  ASSERT_FALSE(HasFatalFailure());

  expect_same_run(due, all);
  ASSERT_FALSE(HasFatalFailure());

  // What the script did: SYNC0 pulses on every slave, the slaves behind the
  // cut in SafeOp with error 0x001B while the others cycled, then all.
  std::array<int, kSlaves> pulses{};
  for (const SyncEdge& e : all.sync) {
    if (e.signal == 0 && e.level) ++pulses[e.slave];
  }
  for (std::size_t i = 0; i < kSlaves; ++i) EXPECT_GT(pulses[i], 300) << "slave " << i;
  std::array<int, kSlaves> drops{};
  for (const AlChange& c : all.al) {
    if ((c.status & esc::bits::kAlErrorInd) != 0) ++drops[c.slave];
  }
  for (std::size_t i = 0; i < kSlaves; ++i) EXPECT_GE(drops[i], 1) << "slave " << i;
  // Slaves 4 and 5 dropped while the master cycled the others.
  EXPECT_LT(std::find_if(all.al.begin(), all.al.end(), [](const AlChange& c) { return c.slave == kCutAfter + 1 && (c.status & esc::bits::kAlErrorInd) != 0; })->t,
            std::find_if(all.al.begin(), all.al.end(), [](const AlChange& c) { return c.slave == 0 && (c.status & esc::bits::kAlErrorInd) != 0; })->t);
  // The due chain polled most slaves at few of the deadlines; the other at all.
  EXPECT_EQ(all.unpolled, 0u);
  EXPECT_GT(due.unpolled, all.deadlines.size() * kSlaves / 2);

}

// A chain of fewer than slave::Chain::kTrackFrom slaves keeps no wake
// times: after each frame it asks every slave, and a poll reads each one's
// visit time from the slave itself (issue 30: the one-drive cycle). The same
// script, three slaves: the same frames, events and registers as a chain
// that polls every slave, while most polls leave most slaves alone.
TEST(ChainPoll, ASmallChainPollsTheDueSlavesAsALargeOneDoes) {
  constexpr std::size_t kFew = 3;
  static_assert(kFew < slave::Chain::kTrackFrom);
  LiveRig due(true, kFew);
  LiveRig all(false, kFew);
  due.run();
  all.run();
  ASSERT_FALSE(HasFatalFailure());
  expect_same_run(due, all);
  EXPECT_GT(due.frames.size(), 1000u);
  EXPECT_EQ(all.unpolled, 0u);
  EXPECT_GT(due.unpolled, all.deadlines.size() * kFew / 2);
}

// Issue 30: a slave's own firmware accesses its ESC whenever it runs, and
// the chain takes the slave's times in right after (Chain::note); an access
// from outside after that (here through an Esc& kept from before, as a PDI
// host or a test holds one) must still make the next poll look at the
// slave again, although the segment's dirty set already held the ESC from
// the firmware's own accesses (what tells is esc::Esc::accessed). The
// access starts SYNC0 over the PDI (the master gave it the sync unit): the
// due chain's polls must return the deadlines, and the pulse come at its
// start time, as with a chain that polls every slave.
TEST(ChainPoll, AnAccessAfterTheSlavesOwnFirmwareRanIsSeenByTheNextPoll) {
  constexpr std::size_t kSlave = 2;
  constexpr std::uint32_t kLeadNs = 200'000;
  constexpr int kMaxPolls = 50;
  constexpr auto kAlPreOp = static_cast<std::uint16_t>(esc::AlState::PreOp);
  std::array<std::vector<Nanoseconds>, 2> deadlines;
  std::array<std::vector<SyncEdge>, 2> edges;
  std::array<std::uint64_t, 2> start{};
  for (int k = 0; k < 2; ++k) {
    InProcess p;
    p.chain.set_polling_due(k == 0);
    p.add_default(kSlaves);
    ASSERT_TRUE(p.master.scan());
    const std::uint16_t station = p.master.slave(kSlave).station_address;
    ASSERT_TRUE(p.master.fpwr_u8(station, esc::reg::kDcBase + esc::dcreg::kCyclicUnitControl,
                                 esc::dcreg::kSyncOwnerPdi));
    esc::Esc& outside = p.chain[kSlave].esc();
    SyncLog log(edges[k], kSlave);
    outside.dc().set_observer(&log);
    // A frame that makes the slave's firmware run (an AL control event):
    // it refuses PreOp without mailbox SMs, writing the AL status and code
    // through the PDI, and the chain notes it.
    ASSERT_TRUE(p.master.fpwr_u16(station, esc::reg::kAlControl, kAlPreOp));
    ASSERT_EQ(std::as_const(p.chain)[kSlave].status().code, esc::AlStatusCode::InvalidMailboxConfigurationPreOp);
    // What was due by now ran: no slave is due by time at the next poll.
    const std::optional<Nanoseconds> before = p.chain.poll(p.clock.now());
    ASSERT_TRUE(!before || *before > p.clock.now() + std::chrono::nanoseconds(kLeadNs));
    // From outside the chain, over the PDI: SYNC0 every cycle from 200 µs on.
    std::uint8_t now[8]{};
    outside.read(esc::reg::kDcBase + esc::dcreg::kSystemTime, now);
    start[k] = load_le<std::uint64_t>(now) + kLeadNs;
    std::uint8_t cycle[4]{};
    store_le<std::uint32_t>(cycle, kCycleNs);
    outside.write(esc::reg::kDcBase + esc::dcreg::kSync0CycleTime, cycle);
    std::uint8_t at[8]{};
    store_le<std::uint64_t>(at, start[k]);
    outside.write(esc::reg::kDcBase + esc::dcreg::kStartTimeCyclicOperation, at);
    const std::uint8_t on[] = {esc::dcreg::kActivateSyncUnit | esc::dcreg::kActivateSync0};
    outside.write(esc::reg::kDcBase + esc::dcreg::kActivation, on);
    // Poll at each deadline returned, as ecat-slave does on a quiet wire,
    // until the first pulse.
    for (int n = 0; n < kMaxPolls && edges[k].empty(); ++n) {
      const std::optional<Nanoseconds> next = p.chain.poll(p.clock.now());
      if (!next) break;
      deadlines[k].push_back(*next);
      p.clock.set(std::max(p.clock.now(), *next));
    }
    outside.dc().set_observer(nullptr);
    ASSERT_FALSE(edges[k].empty()) << (k == 0 ? "due" : "all") << ": no SYNC0 pulse";
  }
  EXPECT_EQ(deadlines[0], deadlines[1]);
  EXPECT_EQ(edges[0], edges[1]);
  EXPECT_EQ(start[0], start[1]);
  EXPECT_TRUE(edges[0].front().level);
}

}  // namespace
}  // namespace ecat::test
