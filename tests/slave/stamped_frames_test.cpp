// Live timing decoupled from scheduling (issue 19): a slave process woken
// late processes each queued frame at the time the kernel stamped it
// (Chain::catch_up), so SYNC0 events and frames keep their order and the DC
// latches see the arrival time. On simulated time, deterministic.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "common/le.hpp"
#include "esc/registers.hpp"
#include "master/coe_client.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

using std::chrono::microseconds;
using std::chrono::milliseconds;

constexpr Nanoseconds kCycle = milliseconds(1);
constexpr std::uint32_t kCycleNs = 1'000'000;
constexpr std::uint16_t kSyncModeDcSync0 = 2;
constexpr std::uint16_t kDcStartTimeCyclic = 0x0990;  // next SYNC0 while active
constexpr std::uint16_t kDcReceiveTimePort0 = 0x0900;

// One slave in DC Sync0 at 1 ms, in Op, with the master's cyclic frame kept
// so it can be replayed at chosen arrival times.
struct DcRig {
  InProcess p;
  std::vector<std::uint8_t> cyclic;

  std::string bring_up() {
    p.add_default();
    auto n = p.master.scan();
    if (!n || *n != 1) return "scan";
    if (!p.master.slave(0).esc.has_dc()) return "no DC";
    if (!p.master.configure_mailbox(0)) return "mailbox";
    auto st = p.master.request_state(0, master::AlState::PreOp);
    if (!st || st->error()) return "preop";
    master::CoeClient coe(p.master, 0);
    for (std::uint16_t obj : {std::uint16_t{0x1C32}, std::uint16_t{0x1C33}}) {
      if (!coe.download_value(obj, 1, kSyncModeDcSync0, 2)) return "sync mode";
    }
    if (!coe.read_pdo_sizes()) return "pdo sizes";
    if (!p.master.configure_process_data()) return "process data";
    if (!p.master.configure_dc(p.clock.now())) return "dc";
    if (!p.master.configure_sync0(0, kCycleNs, 0, milliseconds(5))) return "sync0";
    st = p.master.request_state(0, master::AlState::SafeOp);
    if (!st || st->error()) return "safeop";
    for (int c = 0; c < 20; ++c) (void)p.cycle_once(kCycle);
    st = p.master.request_state(0, master::AlState::Op);
    if (!st || st->error()) return "op";
    p.wire.record_sent(true);
    for (int c = 0; c < 5; ++c) (void)p.cycle_once(kCycle);
    p.wire.record_sent(false);
    cyclic = p.wire.sent_frames().back();
    return "";
  }
  // Clock time of the next SYNC0 pulse of slave 0.
  Nanoseconds next_sync0() {
    esc::Esc& e = p.chain[0].esc();
    std::array<std::uint8_t, 8> b{};
    e.read(kDcStartTimeCyclic, b);
    return e.dc().when_system(load_le<std::uint64_t>(b.data()));
  }
  std::uint32_t missed() { return p.chain[0].status().sync_errors; }

  // Five cycles on time, each frame landing 100 us before the next SYNC0;
  // leaves the clock just after the last pulse and returns the next one.
  Nanoseconds settle_on_time() {
    Nanoseconds pulse = next_sync0() + kCycle;
    for (int c = 0; c < 5; ++c) {
      p.clock.set(pulse - microseconds(100));
      deliver(cyclic, p.clock.now(), p.clock.now());
      pulse += kCycle;
    }
    p.clock.set(pulse - kCycle + microseconds(10));
    (void)p.chain.poll(p.clock.now());
    return pulse;
  }
  // The frame reaches the chain at `now`, stamped `arrival` by the kernel.
  void deliver(std::vector<std::uint8_t> frame, std::optional<Nanoseconds> arrival, Nanoseconds now) {
    const Nanoseconds at = p.chain.catch_up(arrival, now);
    (void)p.chain.pass_frame(frame, at);
    p.chain.run_firmware(at);
  }
};

// BWR 0x0900: latches every port's receive time (ESC datasheet Section II
// 0x0900): Ethernet header, EtherCAT header (length 16, type 1), one datagram.
std::vector<std::uint8_t> latch_frame() {
  return {0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x02, 0x00, 0x00, 0x00, 0x00, 0x01, 0x88, 0xA4,
          0x10, 0x10, 0x08, 0x00, 0x00, 0x00, 0x00, 0x09, 0x04, 0x00, 0x00, 0x00, 0, 0, 0, 0, 0x00, 0x00};
}

TEST(StampedFrames, QueuedFramesAreProcessedWhenTheyArrivedNotWhenTheProcessWoke) {
  DcRig rig;
  const std::string up = rig.bring_up();
  if (up == "no DC") GTEST_SKIP() << "default device without DC";
  ASSERT_EQ(up, "");
  // Settle on time: every cycle's frame lands 100 us before the next SYNC0.
  Nanoseconds pulse = rig.settle_on_time();
  const std::uint32_t missed_before = rig.missed();
  ASSERT_EQ(rig.p.chain[0].status().state, esc::AlState::Op);

  // The process is not scheduled for 3.4 ms: three cyclic frames and a DC
  // latch queue up, each stamped when it arrived, 100 us before a SYNC0.
  const Nanoseconds woke = pulse + milliseconds(2) + microseconds(300);
  rig.p.clock.set(woke);
  for (int k = 0; k < 3; ++k) rig.deliver(rig.cyclic, pulse + k * kCycle - microseconds(100), woke);
  const Nanoseconds latch_arrival = pulse + milliseconds(2) + microseconds(50);
  std::vector<std::uint8_t> latch = latch_frame();
  rig.deliver(latch, latch_arrival, woke);
  (void)rig.p.chain.poll(woke);  // drained: time moves on to the clock

  // Every SYNC0 found the outputs of the frame that arrived before it.
  EXPECT_EQ(rig.missed(), missed_before);
  EXPECT_EQ(rig.p.chain[0].status().state, esc::AlState::Op);
  EXPECT_FALSE(rig.p.chain[0].status().error);
  // The receive-time latch holds the local time at arrival, not at wake-up.
  esc::Esc& e = rig.p.chain[0].esc();
  std::array<std::uint8_t, 4> latched{};
  e.read(kDcReceiveTimePort0, latched);
  EXPECT_EQ(load_le<std::uint32_t>(latched.data()), static_cast<std::uint32_t>(e.dc().local_time(latch_arrival)));
  EXPECT_NE(load_le<std::uint32_t>(latched.data()), static_cast<std::uint32_t>(e.dc().local_time(woke)));
  EXPECT_EQ(rig.p.chain.time_seen(), woke);
}

// The same queue handled as the loop did before (time moved to the wake-up
// first, every frame at the wake-up): the SYNC0 pulses that fell while the
// process slept are seen before the frames that arrived ahead of them, and
// one is counted as a missed SM event. Keeps the test above honest.
TEST(StampedFrames, WithoutTheStampsTheSameQueueCountsAMissedEvent) {
  DcRig rig;
  const std::string up = rig.bring_up();
  if (up == "no DC") GTEST_SKIP() << "default device without DC";
  ASSERT_EQ(up, "");
  Nanoseconds pulse = rig.settle_on_time();
  const std::uint32_t missed_before = rig.missed();
  const Nanoseconds woke = pulse + milliseconds(2) + microseconds(300);
  rig.p.clock.set(woke);
  (void)rig.p.chain.poll(woke);
  for (int k = 0; k < 3; ++k) rig.deliver(rig.cyclic, std::nullopt, woke);
  EXPECT_GT(rig.missed(), missed_before);
}

TEST(StampedFrames, TimeNeverRunsBackwards) {
  InProcess p;
  p.add_default();
  p.clock.set(milliseconds(10));
  (void)p.chain.poll(p.clock.now());
  // A stamp older than what the chain has seen is taken as "just now".
  EXPECT_EQ(p.chain.catch_up(milliseconds(4), milliseconds(12)), milliseconds(10));
  // A stamp from the future (a wall-clock step) is capped at the clock.
  EXPECT_EQ(p.chain.catch_up(milliseconds(20), milliseconds(12)), milliseconds(12));
  EXPECT_EQ(p.chain.catch_up(milliseconds(13), milliseconds(15)), milliseconds(13));
  EXPECT_EQ(p.chain.catch_up(std::nullopt, milliseconds(16)), milliseconds(16));
  EXPECT_EQ(p.chain.time_seen(), milliseconds(16));
}

}  // namespace
}  // namespace ecat::test
