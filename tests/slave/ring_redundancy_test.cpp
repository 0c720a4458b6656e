// Cable redundancy end to end in one process (issue 16 items 4 and 6): five
// generic servos in a ring (the last one's port 1 cabled to the master's
// second port, Chain::connect_redundant), the project's master on a
// RedundantTransport over two in-memory master ports, each port handing its
// frames to the emulated segment at its end (Chain::pass_frame_on) and
// receiving what comes out there. The drives reach Op and follow CSP set
// points; a cable cut in the middle of the ring during cyclic Op, then
// restored, then a cut elsewhere: no cycle lost, every WKC the expected one,
// every drive still commanded and answering, the break located.
#include <gtest/gtest.h>

#include <array>
#include <cstdlib>
#include <deque>
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

constexpr std::size_t kDrives = 5;
constexpr Nanoseconds kWireTime = std::chrono::microseconds(5);
constexpr Nanoseconds kCycle = std::chrono::milliseconds(1);
// Generic servo default PDOs (xml/devices/generic-servo.xml): 1600h and 1A00h.
constexpr std::size_t kControlword = 0, kTargetPosition = 2, kModes = 12;
constexpr std::size_t kStatusword = 0, kActualPosition = 2;
constexpr std::uint16_t kWkcPerDrive = 3;  // LRW: outputs +2, inputs +1
constexpr std::uint8_t kCsp = 8;

struct Ring;

// One master port: a frame sent here enters the ring at this end; the frame
// is queued on the master port it comes out of.
class MasterPort final : public transport::Transport {
 public:
  MasterPort(Ring& ring, unsigned port) : ring_(ring), port_(port) {}
  Expected<void, transport::TransportError> send(ConstBytes frame) override;
  Expected<std::size_t, transport::TransportError> receive(Bytes buffer, Nanoseconds) override {
    return queue.pop(buffer);
  }
  ecat::test::FrameQueue queue;

 private:
  Ring& ring_;
  unsigned port_;
};

struct Ring {
  ManualClock clock;
  slave::Chain chain{clock};
  std::array<MasterPort, esc::kMasterPorts> ports{MasterPort{*this, 0}, MasterPort{*this, 1}};
  master::RedundantTransport red{ports[0], ports[1], clock};
  master::Master master{red, clock};
  std::uint64_t lost = 0;

  Ring() {
    auto d = esi::load_device_file(std::string(ECAT_SOURCE_DIR) + "/xml/devices/generic-servo.xml");
    if (!d) throw std::runtime_error(d.error().to_string());
    for (std::size_t i = 0; i < kDrives; ++i) {
      auto ok = chain.add(*d, {});
      if (!ok) throw std::runtime_error(ok.error());
    }
    auto ok = chain.connect_redundant(kDrives - 1, esc::kDownstreamPort);
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
    if (!n || *n != kDrives) return "scan";
    for (std::size_t i = 0; i < kDrives; ++i) {
      if (!master.configure_mailbox(i)) return "mailbox";
      auto st = master.request_state(i, master::AlState::PreOp);
      if (!st || st->error()) return "preop";
      master::CoeClient coe(master, i);
      if (!coe.read_pdo_sizes()) return "pdo sizes";
    }
    if (!master.configure_process_data()) return "process data";
    for (std::size_t i = 0; i < kDrives; ++i) {
      auto st = master.request_state(i, master::AlState::SafeOp);
      if (!st || st->error()) return "safeop";
    }
    for (int c = 0; c < 10; ++c) (void)cycle(0x0000, 0);
    for (std::size_t i = 0; i < kDrives; ++i) {
      auto st = master.request_state(i, master::AlState::Op);
      if (!st || st->error()) return "op";
    }
    return "";
  }

  // Drive i gets target (i + 1) * base; one cycle; returns the WKC (0 if the cycle failed).
  std::uint16_t cycle(std::uint16_t controlword, std::int32_t base) {
    for (std::size_t i = 0; i < kDrives; ++i) {
      std::uint8_t* out = master.outputs(i).data();
      store_le<std::uint16_t>(out + kControlword, controlword);
      store_le<std::uint32_t>(out + kTargetPosition, static_cast<std::uint32_t>(base * static_cast<std::int32_t>(i + 1)));
      out[kModes] = kCsp;
    }
    clock.advance(kCycle);
    (void)chain.poll(clock.now());
    auto r = master.exchange_process_data();
    return r ? r->wkc : 0;
  }
  std::uint16_t statusword(std::size_t i) { return load_le<std::uint16_t>(master.inputs(i).data() + kStatusword); }
  std::int32_t actual(std::size_t i) {
    return static_cast<std::int32_t>(load_le<std::uint32_t>(master.inputs(i).data() + kActualPosition));
  }
};

Expected<void, transport::TransportError> MasterPort::send(ConstBytes frame) {
  ring_.carry(std::vector<std::uint8_t>(frame.begin(), frame.end()), port_);
  return {};
}

TEST(RingRedundancy, CutsDuringCyclicOpLoseNoCycle) {
  Ring r;
  ASSERT_EQ(r.bring_up(), "");
  EXPECT_EQ(r.red.state(), master::RingState::Intact);
  const std::uint16_t expected = kWkcPerDrive * kDrives;
  ASSERT_EQ(r.master.expected_wkc(), expected);
  // Shutdown, switch on, enable operation (CiA402 transitions 2, 3, 4).
  for (std::uint16_t cw : {std::uint16_t{0x0006}, std::uint16_t{0x0007}, std::uint16_t{0x000F}}) {
    for (int c = 0; c < 5; ++c) ASSERT_EQ(r.cycle(cw, 0), expected);
  }
  for (std::size_t i = 0; i < kDrives; ++i) EXPECT_EQ(r.statusword(i) & 0x027F, 0x0237) << i;

  // A ramp of 100 increments per cycle (x drive number) over 600 cycles:
  // intact, cut between drives 2 and 3, restored, cut between 0 and 1, restored.
  struct Phase {
    int from;
    std::optional<std::size_t> cut_after;  // the cable on port 1 of this drive is cut
  };
  const std::array<Phase, 5> phases{{{0, {}}, {100, 2}, {250, {}}, {350, 0}, {500, {}}}};
  std::array<std::int32_t, kDrives> last{};
  std::size_t phase = 0;
  std::optional<std::size_t> cut;
  for (int c = 0; c < 600; ++c) {
    if (phase < phases.size() && phases[phase].from == c) {
      if (cut) {
        ASSERT_TRUE(r.chain.segment().set_link(*cut, esc::kDownstreamPort, true));
      }
      cut = phases[phase].cut_after;
      if (cut) {
        ASSERT_TRUE(r.chain.segment().set_link(*cut, esc::kDownstreamPort, false));
      }
      ++phase;
    }
    ASSERT_EQ(r.cycle(0x000F, 100 * c), expected) << "cycle " << c;
    if (cut) {
      ASSERT_EQ(r.red.state(), master::RingState::Broken) << "cycle " << c;
      auto at = r.red.ring_break(kDrives);
      ASSERT_TRUE(at) << c;
      EXPECT_EQ(at->last_primary_side, *cut);
      EXPECT_EQ(at->first_secondary_side, *cut + 1);
    } else {
      ASSERT_EQ(r.red.state(), master::RingState::Intact) << "cycle " << c;
    }
    for (std::size_t i = 0; i < kDrives; ++i) {
      // Inputs every cycle: each drive moves on its own ramp, never back.
      const std::int32_t a = r.actual(i);
      if (c > 20) {
        EXPECT_GT(a, last[i]) << "cycle " << c << " drive " << i;
      }
      last[i] = a;
      ASSERT_EQ(r.statusword(i) & 0x006F, 0x0027) << "cycle " << c << " drive " << i;
    }
  }
  // Outputs every cycle: each drive followed its own set point, (i + 1) x 100
  // per cycle. The plants are alike and linear, so drive i lags its ramp by
  // (i + 1) times what drive 0 lags (about 11 cycles of ramp in this plant); a
  // set point lost or given to the wrong drive during a cut breaks the ratio.
  const std::int32_t lag0 = 100 * 599 - r.actual(0);
  EXPECT_GT(lag0, 0);
  EXPECT_LT(lag0, 20 * 100);
  for (std::size_t i = 0; i < kDrives; ++i) {
    const auto k = static_cast<std::int32_t>(i + 1);
    EXPECT_LE(std::abs((100 * 599 * k - r.actual(i)) - k * lag0), k) << i;
    auto st = r.master.read_al_status(i);
    ASSERT_TRUE(st);
    EXPECT_EQ(st->raw, 0x0008) << i;  // Op, no error
  }
  EXPECT_EQ(r.lost, 0u);  // every frame came back on one master port or the other
  EXPECT_EQ(r.red.stats().no_reply, 0u);
  EXPECT_EQ(r.red.stats().broken, 150u + 150u);
  EXPECT_GT(r.red.stats().resent, 0u);
}

}  // namespace
}  // namespace ecat::test
