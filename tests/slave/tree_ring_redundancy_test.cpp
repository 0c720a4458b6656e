// Cable redundancy through a tree (issue 16): a coupler on the master's
// first port, a junction on the coupler's E-bus port 1, a branch of two
// drives on the junction's port 3 (a stub), and the junction's port 2 branch
// of two drives whose last one's port 1 returns to the master's second port.
// The junction's port 2 is the last port of its processing order (0 -> PU ->
// 3 -> 1 -> 2, Section I §3.2 Table 9) and the coupler's port 2 is free, so
// the intact ring's frame passes every slave before it reaches the second
// port. The project's master on a RedundantTransport brings the drives to Op
// with CSP; then each cable of the ring is cut in turn during cyclic Op and
// restored: every cycle returns the full WKC, every drive follows its own
// set point, the ring state and the break position are right.
//
//   master port 0 ── C ──1── J ──3── A1 ──1── A2        (stub)
//                              └─2── B1 ──1── B2 ──1── master port 1
#include <gtest/gtest.h>

#include <array>
#include <cstdlib>
#include <deque>
#include <optional>
#include <vector>

#include "common/le.hpp"
#include "esi/device_loader.hpp"
#include "master/coe_client.hpp"
#include "master/master.hpp"
#include "master/redundant_transport.hpp"
#include "slave/chain.hpp"
#include "tests/support/frame_queue.hpp"

namespace ecat::test {
namespace {

constexpr Nanoseconds kWireTime = std::chrono::microseconds(5);
constexpr Nanoseconds kCycle = std::chrono::milliseconds(1);
// Positions in frame order (auto-increment): C, J, A1, A2, B1, B2.
constexpr std::size_t kSlaves = 6;
constexpr std::size_t kC = 0, kJ = 1, kA1 = 2, kA2 = 3, kB1 = 4, kB2 = 5;
constexpr std::array<std::size_t, 4> kDrives{kA1, kA2, kB1, kB2};
// Generic servo default PDOs (xml/devices/generic-servo.xml): 1600h and 1A00h.
constexpr std::size_t kControlword = 0, kTargetPosition = 2, kModes = 12;
constexpr std::size_t kStatusword = 0, kActualPosition = 2;
constexpr std::uint16_t kWkcPerDrive = 3;  // LRW: outputs +2, inputs +1
constexpr std::uint8_t kCsp = 8;

od::DeviceDescription load(const std::string& name) {
  auto d = esi::load_device_file(std::string(ECAT_SOURCE_DIR) + "/xml/devices/" + name);
  if (!d) throw std::runtime_error(d.error().to_string());
  return std::move(*d);
}

struct TreeRing;

// One master port: a frame sent here enters the segment at this end and is
// queued on the master port it comes out of.
class MasterPort final : public transport::Transport {
 public:
  MasterPort(TreeRing& ring, unsigned port) : ring_(ring), port_(port) {}
  Expected<void, transport::TransportError> send(ConstBytes frame) override;
  Expected<std::size_t, transport::TransportError> receive(Bytes buffer, Nanoseconds) override {
    return queue.pop(buffer);
  }
  ecat::test::FrameQueue queue;

 private:
  TreeRing& ring_;
  unsigned port_;
};

struct TreeRing {
  ManualClock clock;
  slave::Chain chain{clock};
  std::array<MasterPort, esc::kMasterPorts> ports{MasterPort{*this, 0}, MasterPort{*this, 1}};
  master::RedundantTransport red{ports[0], ports[1], clock};
  master::Master master{red, clock};
  std::uint64_t lost = 0;

  TreeRing() {
    check(chain.add(load("coupler-3port.xml"), {}));
    check(chain.attach(load("junction-4port.xml"), {}, kC, 1));
    const od::DeviceDescription servo = load("generic-servo.xml");
    check(chain.attach(servo, {}, kJ, 3));   // A1
    check(chain.attach(servo, {}, kA1, 1));  // A2
    check(chain.attach(servo, {}, kJ, 2));   // B1
    check(chain.attach(servo, {}, kB1, 1));  // B2
    check(chain.connect_redundant(kB2, esc::kDownstreamPort));
  }
  static void check(const Expected<void, std::string>& ok) {
    if (!ok) throw std::runtime_error(ok.error());
  }

  void carry(std::vector<std::uint8_t> f, unsigned port) {
    clock.advance(kWireTime);
    const esc::Delivery d = chain.pass_frame_on(f, clock.now(), port);
    chain.run_firmware(clock.now());
    if (d.returned()) {
      ports[d.master_port].queue.push_back(std::move(f));
    } else {
      ++lost;
    }
  }

  std::string bring_up() {
    auto n = master.scan();
    if (!n || *n != kSlaves) return "scan";
    for (std::size_t i = 0; i < kSlaves; ++i) {
      const bool drive = i >= kA1;  // coupler and junction have no mailbox
      if (drive && !master.configure_mailbox(i)) return "mailbox";
      auto st = master.request_state(i, master::AlState::PreOp);
      if (!st || st->error()) return "preop";
      if (drive && !master::CoeClient(master, i).read_pdo_sizes()) return "pdo sizes";
    }
    if (!master.configure_process_data()) return "process data";
    for (std::size_t i = 0; i < kSlaves; ++i) {
      auto st = master.request_state(i, master::AlState::SafeOp);
      if (!st || st->error()) return "safeop";
    }
    for (int c = 0; c < 10; ++c) (void)cycle(0x0000, 0);
    for (std::size_t i = 0; i < kSlaves; ++i) {
      auto st = master.request_state(i, master::AlState::Op);
      if (!st || st->error()) return "op";
    }
    return "";
  }

  // Drive k (0..3) gets target (k + 1) * base; one cycle; returns the WKC (0 if the cycle failed).
  std::uint16_t cycle(std::uint16_t controlword, std::int32_t base) {
    for (std::size_t k = 0; k < kDrives.size(); ++k) {
      std::uint8_t* out = master.outputs(kDrives[k]).data();
      store_le<std::uint16_t>(out + kControlword, controlword);
      store_le<std::uint32_t>(out + kTargetPosition,
                              static_cast<std::uint32_t>(base * static_cast<std::int32_t>(k + 1)));
      out[kModes] = kCsp;
    }
    clock.advance(kCycle);
    (void)chain.poll(clock.now());
    auto r = master.exchange_process_data();
    return r ? r->wkc : 0;
  }
  std::uint16_t statusword(std::size_t k) {
    return load_le<std::uint16_t>(master.inputs(kDrives[k]).data() + kStatusword);
  }
  std::int32_t actual(std::size_t k) {
    return static_cast<std::int32_t>(load_le<std::uint32_t>(master.inputs(kDrives[k]).data() + kActualPosition));
  }
};

Expected<void, transport::TransportError> MasterPort::send(ConstBytes frame) {
  ring_.carry(std::vector<std::uint8_t>(frame.begin(), frame.end()), port_);
  return {};
}

// A cable of the ring, by one end (slave position, port), and what the
// master sees while it is cut.
struct Cut {
  std::size_t slave;
  unsigned port;
  master::RingState state;
  std::size_t last_primary_side;  // for Broken: the break lies after this position
};

TEST(TreeRingRedundancy, EveryRingCableCutDuringCyclicOpLosesNoCycle) {
  TreeRing r;
  ASSERT_EQ(r.bring_up(), "");
  EXPECT_EQ(r.red.state(), master::RingState::Intact);
  const std::uint16_t expected = kWkcPerDrive * kDrives.size();
  ASSERT_EQ(r.master.expected_wkc(), expected);
  // The scan found the tree: J on C port 1, A1 on J port 3, B1 on J port 2.
  EXPECT_EQ(r.master.slave(kJ).topology.parent, kC);
  EXPECT_EQ(r.master.slave(kJ).topology.parent_port, 1u);
  EXPECT_EQ(r.master.slave(kA1).topology.parent, kJ);
  EXPECT_EQ(r.master.slave(kA1).topology.parent_port, 3u);
  EXPECT_EQ(r.master.slave(kB1).topology.parent, kJ);
  EXPECT_EQ(r.master.slave(kB1).topology.parent_port, 2u);
  for (std::uint16_t cw : {std::uint16_t{0x0006}, std::uint16_t{0x0007}, std::uint16_t{0x000F}}) {
    for (int c = 0; c < 5; ++c) ASSERT_EQ(r.cycle(cw, 0), expected);
  }
  for (std::size_t k = 0; k < kDrives.size(); ++k) EXPECT_EQ(r.statusword(k) & 0x027F, 0x0237) << k;

  // Every cable of the ring, 60 cycles cut each, 20 intact in between.
  const std::array<Cut, 5> cuts{{
      {kC, 0, master::RingState::PrimaryLinkDown, 0},  // master port 0 - C
      {kC, 1, master::RingState::Broken, kC},          // C - J (E-bus)
      {kJ, 2, master::RingState::Broken, kA2},         // J port 2 - B1: C, J, A1, A2 before it
      {kB1, 1, master::RingState::Broken, kB1},        // B1 - B2
      {kB2, 1, master::RingState::SecondaryLinkDown, 0},  // B2 - master port 1
  }};
  constexpr int kIntact = 20, kCutCycles = 60;
  std::array<std::int32_t, kDrives.size()> last{};
  int c = 0;
  auto run = [&](int cycles, const Cut* cut) {
    for (int n = 0; n < cycles; ++n, ++c) {
      ASSERT_EQ(r.cycle(0x000F, 100 * c), expected) << "cycle " << c;
      if (cut) {
        ASSERT_EQ(r.red.state(), cut->state) << "cycle " << c;
        if (cut->state == master::RingState::Broken) {
          auto at = r.red.ring_break(kSlaves);
          ASSERT_TRUE(at) << c;
          EXPECT_EQ(at->last_primary_side, cut->last_primary_side) << c;
          EXPECT_EQ(at->first_secondary_side, cut->last_primary_side + 1) << c;
        }
      } else {
        ASSERT_EQ(r.red.state(), master::RingState::Intact) << "cycle " << c;
      }
      for (std::size_t k = 0; k < kDrives.size(); ++k) {
        const std::int32_t a = r.actual(k);
        if (c > 20) {
          EXPECT_GT(a, last[k]) << "cycle " << c << " drive " << k;
        }
        last[k] = a;
        ASSERT_EQ(r.statusword(k) & 0x006F, 0x0027) << "cycle " << c << " drive " << k;
      }
    }
  };
  run(kIntact, nullptr);
  for (const Cut& cut : cuts) {
    ASSERT_TRUE(r.chain.segment().set_link(cut.slave, cut.port, false));
    run(kCutCycles, &cut);
    ASSERT_TRUE(r.chain.segment().set_link(cut.slave, cut.port, true));
    run(kIntact, nullptr);
  }
  // Each drive followed its own ramp ((k + 1) x 100 per cycle): drive k lags
  // (k + 1) times what drive 0 lags; a set point lost or given to the wrong
  // drive during a cut breaks the ratio.
  const std::int32_t end = 100 * (c - 1);
  const std::int32_t lag0 = end - r.actual(0);
  EXPECT_GT(lag0, 0);
  EXPECT_LT(lag0, 20 * 100);
  for (std::size_t k = 0; k < kDrives.size(); ++k) {
    const auto m = static_cast<std::int32_t>(k + 1);
    EXPECT_LE(std::abs((end * m - r.actual(k)) - m * lag0), m) << k;
  }
  for (std::size_t i = 0; i < kSlaves; ++i) {
    auto st = r.master.read_al_status(i);
    ASSERT_TRUE(st);
    EXPECT_EQ(st->raw, 0x0008) << i;  // Op, no error
  }
  EXPECT_EQ(r.red.stats().no_reply, 0u);
  EXPECT_EQ(r.red.stats().broken, 3u * kCutCycles);
  EXPECT_EQ(r.red.stats().primary_down, std::uint64_t{kCutCycles});
  EXPECT_EQ(r.red.stats().secondary_down, std::uint64_t{kCutCycles});
}

// A stub branch is not part of the ring: cutting J port 3 leaves A1 and A2
// unreachable (no second way to them), the rest keeps running.
TEST(TreeRingRedundancy, StubCutLosesOnlyTheStub) {
  TreeRing r;
  ASSERT_EQ(r.bring_up(), "");
  const std::uint16_t expected = kWkcPerDrive * kDrives.size();
  for (int c = 0; c < 5; ++c) ASSERT_EQ(r.cycle(0x0006, 0), expected);
  ASSERT_TRUE(r.chain.segment().set_link(kJ, 3, false));
  EXPECT_EQ(r.cycle(0x0006, 0), expected - 2 * kWkcPerDrive);
  EXPECT_EQ(r.red.state(), master::RingState::Intact);  // the ring itself is whole
  ASSERT_TRUE(r.chain.segment().set_link(kJ, 3, true));
  EXPECT_EQ(r.cycle(0x0006, 0), expected);
}

}  // namespace
}  // namespace ecat::test
