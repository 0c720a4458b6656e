// The SYNC0 start when the master stalls (master::Master::configure_sync0):
// the master reads the slave's system time (0x0910), computes a start time
// start_delay ahead, and activates the SYNC unit (0x0981 = 3). A master held
// up between the read and the activation for longer than start_delay (a
// loaded host: ecat-master's start-up gaps reached 42 ms among scripts/test's
// live tests, against its 20 ms start delay) activates a unit whose start time has
// passed, and the ESC then waits for the 64-bit system time to wrap (ESC
// datasheet Section II 0x0981, docs/dc.md "SYNC generation"): no SYNC0 ever,
// and the slave refuses Op with 002Dh. The master reads 0x0910 and 0x0990
// back after the activation and programs the unit again when its start was
// missed. Against the emulated ESC on simulated time, the stall injected on
// the wire in front of the activating datagram.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "common/frame_parser.hpp"
#include "common/le.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

using std::chrono::milliseconds;

constexpr std::uint16_t kSystemTime = 0x0910;
constexpr std::uint16_t kDcActivation = 0x0981;
constexpr std::uint16_t kStartTimeCyclic = 0x0990;  // read: the next SYNC0 while running
constexpr std::uint8_t kActivateCyclicSync0 = 0x03;
constexpr std::uint32_t kCycleNs = 1'000'000;
constexpr Nanoseconds kStartDelay = milliseconds(20);
constexpr Nanoseconds kStall = milliseconds(30);  // longer than kStartDelay

struct StalledStart : InProcess {
  int stalls = 0;                        // activations still to be held up by kStall
  std::vector<std::uint8_t> activations;  // every value written to 0x0981, in order

  StalledStart() {
    add_default(1);
    wire.set_processor([this](Bytes frame) {
      if (auto view = parse_frame(frame)) {
        view->for_each([&](DatagramView d) {
          if (d.command() != Command::Fpwr || d.ado() != kDcActivation || d.data().empty()) return;
          activations.push_back(d.data()[0]);
          if (d.data()[0] == kActivateCyclicSync0 && stalls > 0) {
            --stalls;
            clock.advance(kStall);
          }
        });
      }
      clock.advance(kWireTime);
      (void)chain.process_frame(frame, clock.now());
    });
  }
  std::uint64_t next_sync0() {
    std::array<std::uint8_t, 8> b{};
    chain[0].esc().read(kStartTimeCyclic, b);
    return load_le<std::uint64_t>(b.data());
  }
  std::uint64_t system_time() {
    std::array<std::uint8_t, 8> b{};
    chain[0].esc().read(kSystemTime, b);
    return load_le<std::uint64_t>(b.data());
  }
};

TEST(Sync0Start, WithoutAStallTheUnitIsProgrammedOnce) {
  StalledStart r;
  ASSERT_EQ(r.master.scan().value_or(0), 1u);
  auto start = r.master.configure_sync0(0, kCycleNs, 0, kStartDelay);
  ASSERT_TRUE(start) << master::describe(start.error());
  EXPECT_EQ(r.activations, (std::vector<std::uint8_t>{0x00, kActivateCyclicSync0}));
  EXPECT_EQ(r.master.sync0_started(0).value_or(false), true);
  auto nobody = r.master.sync0_started(1);  // no second slave
  ASSERT_FALSE(nobody);
  EXPECT_EQ(nobody.error(), master::MasterError::InvalidArgument);
  EXPECT_EQ(*start % kCycleNs, 0u);
  EXPECT_EQ(r.next_sync0(), *start);  // ahead, not yet reached
  EXPECT_GT(*start, r.system_time());
  r.advance(milliseconds(25));
  // Running: the next pulse is a whole number of cycles after the start, ahead of now.
  EXPECT_GT(r.next_sync0(), *start);
  EXPECT_EQ((r.next_sync0() - *start) % kCycleNs, 0u);
  EXPECT_GT(r.next_sync0(), r.system_time());
}

TEST(Sync0Start, AStalledActivationIsProgrammedAgain) {
  StalledStart r;
  ASSERT_EQ(r.master.scan().value_or(0), 1u);
  r.stalls = 1;
  auto start = r.master.configure_sync0(0, kCycleNs, 0, kStartDelay);
  ASSERT_TRUE(start) << master::describe(start.error());
  EXPECT_EQ(r.activations, (std::vector<std::uint8_t>{0x00, kActivateCyclicSync0, 0x00, kActivateCyclicSync0}));
  // The second start lies ahead of the time after the stall: SYNC0 runs.
  EXPECT_EQ(r.next_sync0(), *start);
  EXPECT_GT(*start, r.system_time());
  r.advance(milliseconds(25));
  EXPECT_GT(r.next_sync0(), *start);
  EXPECT_GT(r.next_sync0(), r.system_time());
}

// Every attempt stalled: the master says so, and the unit it leaves behind
// (the failure the check guards against) fires no SYNC0: it waits for the wrap.
TEST(Sync0Start, EveryAttemptStalledIsAnErrorAndTheUnitWaits) {
  StalledStart r;
  ASSERT_EQ(r.master.scan().value_or(0), 1u);
  r.stalls = static_cast<int>(master::Master::kSync0StartAttempts);
  auto start = r.master.configure_sync0(0, kCycleNs, 0, kStartDelay);
  ASSERT_FALSE(start);
  EXPECT_EQ(start.error(), master::MasterError::Sync0StartMissed);
  EXPECT_EQ(r.activations.size(), 2u * master::Master::kSync0StartAttempts);
  const std::uint64_t waiting = r.next_sync0();
  EXPECT_LT(waiting, r.system_time());
  r.advance(milliseconds(100));
  EXPECT_EQ(r.next_sync0(), waiting);  // no pulse: it waits for the wrap
}

}  // namespace
}  // namespace ecat::test
