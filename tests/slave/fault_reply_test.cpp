// The reply faults of the catalogue (docs/faults.md, issue 26 item 2):
// replies delayed, duplicated or replaced by the one before, as a switch or
// a congested host does it. The project's master over the in-process wire
// shows what each does to a master: the exact counts of stale frames and
// timeouts in its link statistics, and the right values once the fault is
// spent or cleared.
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "slave/faults/reply_faults.hpp"
#include "tests/slave/fault_rig.hpp"

namespace ecat::test {
namespace {

using slave::FaultId;
using slave::FaultRequest;

constexpr std::uint16_t kStationAddress = 0x0010;

// Two generic servos, scanned.
struct ReplyRig : FaultRig {
  ReplyRig() : FaultRig(2) { EXPECT_EQ(master.scan().value_or(0), 2u); }
  master::LinkStats stats() { return master.link().stats(); }
  // Register 0x0010 of slave i read back: its own station address.
  std::optional<std::uint16_t> station(std::size_t i) {
    auto v = master.fprd_u16(master.slave(i).station_address, kStationAddress);
    return v ? std::optional<std::uint16_t>(*v) : std::nullopt;
  }
  std::uint16_t expected_station(std::size_t i) { return master.slave(i).station_address; }
};

// A duplicate comes after the real reply: the read succeeds, and the next
// exchange finds the copy first (index of the frame before): one stale frame.
TEST(FaultReply, DuplicateIsReadAsAStaleFrame) {
  ReplyRig r;
  const master::LinkStats before = r.stats();
  const FaultId id = r.engage("duplicate_frames");  // count 1
  EXPECT_EQ(r.station(1), r.expected_station(1));
  EXPECT_EQ(r.events, (std::vector<std::pair<FaultId, bool>>{{id, true}, {id, false}}));  // spent at once
  EXPECT_EQ(r.station(0), r.expected_station(0));
  EXPECT_EQ(r.stats().stale_replies - before.stale_replies, 1u);
  EXPECT_EQ(r.stats().timeouts - before.timeouts, 0u);
  EXPECT_EQ(r.stats().frames_received - before.frames_received, 2u);
}

// A replayed frame: the first reply under the rule goes out (it is the one
// replayed); the master's next frame gets that reply instead of its own
// (stale) and times out; its retry gets the real one.
TEST(FaultReply, ReplayGivesThePreviousReplyOnce) {
  ReplyRig r;
  const master::LinkStats before = r.stats();
  const FaultId id = r.engage("replay_frames");
  EXPECT_EQ(r.station(0), r.expected_station(0));
  EXPECT_EQ(r.station(1), r.expected_station(1));
  EXPECT_EQ(r.stats().stale_replies - before.stale_replies, 1u);
  EXPECT_EQ(r.stats().timeouts - before.timeouts, 1u);
  EXPECT_EQ(r.stats().frames_sent - before.frames_sent, 3u);
  EXPECT_EQ(r.events.back(), std::make_pair(id, false));
  EXPECT_TRUE(r.faults.engaged().empty());
}

// Held replies: every attempt of the master times out (the reply is not
// back within its wait); once time passes the held frames arrive late and
// the master throws them away as stale; cleared, reads work again.
TEST(FaultReply, DelayHoldsRepliesUntilTheirTime) {
  ReplyRig r;
  const master::LinkStats before = r.stats();
  const FaultId id = r.engage("delay_frames", std::nullopt, {{"us", 500}});
  EXPECT_FALSE(r.station(1));  // the master's 1 + 3 retries, none answered in time
  EXPECT_EQ(r.stats().timeouts - before.timeouts, 4u);
  const auto due = r.faults.next_reply_due();
  ASSERT_TRUE(due);
  EXPECT_GT(*due, r.clock.now());
  EXPECT_LE(*due - r.clock.now(), std::chrono::microseconds(500));
  ASSERT_TRUE(r.faults.clear(id));
  r.clock.advance(std::chrono::milliseconds(1));
  EXPECT_EQ(r.station(1), r.expected_station(1));  // the 4 late frames first, then its own
  EXPECT_EQ(r.stats().stale_replies - before.stale_replies, 4u);
  EXPECT_FALSE(r.faults.next_reply_due());
}

// Bad parameters are refused and nothing changes.
TEST(FaultReply, RefusesBadParameters) {
  ReplyRig r;
  const std::pair<FaultRequest, std::string> bad[] = {
      {{"delay_frames", std::nullopt, std::nullopt, {}}, "delay_frames: parameter 'us' is required"},
      {{"delay_frames", std::nullopt, std::nullopt, {{"us", 0}}}, "delay_frames: us = 0 is out of range"},
      {{"duplicate_frames", std::nullopt, std::nullopt, {{"us", 5}}}, "duplicate_frames: unknown parameter 'us'"},
      {{"replay_frames", 0, std::nullopt, {}}, "replay_frames: takes no slave"},
  };
  r.expect_refused(bad);
  EXPECT_EQ(r.station(1), r.expected_station(1));
}

// The outbox is fixed: more delayed frames than it holds are lost and counted.
TEST(FaultReply, OutboxOverflowIsCounted) {
  slave::faults::ReplyFaults f;
  f.add({1, slave::faults::ReplyRule::Kind::Delay, std::chrono::milliseconds(1), 0, true});
  const std::array<std::uint8_t, 60> frame{};
  for (std::size_t i = 0; i < slave::faults::ReplyFaults::kOutboxFrames + 3; ++i) {
    EXPECT_TRUE(f.after_return(frame, 0, Nanoseconds{0}));
  }
  EXPECT_EQ(f.overflowed(), 3u);
  std::array<std::uint8_t, slave::faults::ReplyFaults::kMaxFrame> out{};
  EXPECT_FALSE(f.take_due(std::chrono::microseconds(999), out));
  std::size_t n = 0;
  while (f.take_due(std::chrono::milliseconds(1), out)) ++n;
  EXPECT_EQ(n, slave::faults::ReplyFaults::kOutboxFrames);
}

}  // namespace
}  // namespace ecat::test
