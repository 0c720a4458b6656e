// unplug (docs/faults.md, issue 26 item 2 "a slave unplugged and plugged
// back (hot connect)"): every cable of a slave pulled while its power stays
// on, then plugged back. Unlike power_cycle the slave keeps its station
// address and its state machine ran on: what the master finds after the
// hot connect is the slave as the unplugged time left it.
#include <gtest/gtest.h>

#include "common/le.hpp"
#include "tests/slave/fault_rig.hpp"

namespace ecat::test {
namespace {

using slave::FaultId;
using slave::FaultRequest;

constexpr Nanoseconds kCycle = std::chrono::milliseconds(1);
constexpr std::uint16_t kStationAddress = 0x0010, kDlStatus = 0x0110, kAlStatus = 0x0130, kAlStatusCode = 0x0134;
constexpr std::uint16_t kLostLinkCounters = 0x0310;  // + port
constexpr std::uint16_t kLinkPort0 = 0x0010, kLinkPort1 = 0x0020;  // DL status bits 4+n
constexpr std::uint16_t kSafeOpError = 0x14, kOp = 0x08;
constexpr std::uint16_t kSmWatchdog = 0x001B;
// Three servos in Op, each with RxPDO and TxPDO: an LRW counts 3 per slave.
constexpr std::uint16_t kLrwWkcPerSlave = 3;

TEST(FaultUnplug, PulledWithPowerOnThenPluggedBackAsItWas) {
  FaultRig r(3);
  ASSERT_EQ(r.bring_up(kCycle), "");
  const std::uint16_t station1 = r.master.slave(1).station_address;
  const std::uint16_t station2 = r.master.slave(2).station_address;
  auto full = r.cycle_once(kCycle);
  ASSERT_TRUE(full);
  ASSERT_EQ(full->wkc, 3 * kLrwWkcPerSlave);

  const FaultId id = r.engage("unplug", 1);
  EXPECT_EQ(r.master.count_slaves().value_or(0), 1u);  // slave 1 and the one behind it are gone
  auto cut = r.cycle_once(kCycle);
  ASSERT_TRUE(cut);
  EXPECT_EQ(cut->wkc, kLrwWkcPerSlave);  // slave 0 alone
  EXPECT_EQ(r.master.fprd_u8(r.master.slave(0).station_address, kLostLinkCounters + 1).value_or(0xEE), 1);
  // Its ESC runs on behind the pulled cables: no frames, so its process-data
  // watchdog expires and its firmware leaves Op (power is on).
  for (int c = 0; c < 300; ++c) (void)r.cycle_once(kCycle);
  EXPECT_FALSE(r.master.fprd_u16(station1, kAlStatus));  // not reachable

  ASSERT_TRUE(r.faults.clear(id));
  EXPECT_EQ(r.master.count_slaves().value_or(0), 3u);
  // No new scan: it kept the station address the master gave it.
  EXPECT_EQ(r.master.fprd_u16(station1, kStationAddress).value_or(0), station1);
  EXPECT_EQ(r.master.fprd_u16(station1, kAlStatus).value_or(0), kSafeOpError);
  EXPECT_EQ(r.master.fprd_u16(station1, kAlStatusCode).value_or(0), kSmWatchdog);
  EXPECT_EQ(r.master.fprd_u16(station2, kAlStatus).value_or(0), kSafeOpError);  // cut off too
  const std::uint16_t dl = r.master.fprd_u16(station1, kDlStatus).value_or(0);
  EXPECT_EQ(dl & (kLinkPort0 | kLinkPort1), kLinkPort0 | kLinkPort1);  // both links back
  EXPECT_EQ(r.master.fprd_u8(station1, kLostLinkCounters + 0).value_or(0xEE), 1);
  EXPECT_EQ(r.master.fprd_u8(station1, kLostLinkCounters + 1).value_or(0xEE), 1);
  EXPECT_EQ(r.master.fprd_u8(station2, kLostLinkCounters + 0).value_or(0xEE), 1);
  EXPECT_EQ(r.master.fprd_u16(r.master.slave(0).station_address, kAlStatus).value_or(0), kOp);
  // The master acknowledges the error and brings both back to Op.
  for (std::size_t i : {std::size_t{1}, std::size_t{2}}) {
    auto st = r.master.request_state(i, master::AlState::SafeOp, true);
    ASSERT_TRUE(st) << i;
  }
  for (int c = 0; c < 5; ++c) (void)r.cycle_once(kCycle);
  for (std::size_t i : {std::size_t{1}, std::size_t{2}}) {
    auto st = r.master.request_state(i, master::AlState::Op);
    ASSERT_TRUE(st) << i;
    EXPECT_EQ(st->raw, kOp) << i;
  }
  auto back = r.cycle_once(kCycle);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->wkc, 3 * kLrwWkcPerSlave);
}

TEST(FaultUnplug, RefusedTwiceAndBesidePowerCycle) {
  FaultRig r(2);
  ASSERT_EQ(r.master.scan().value_or(0), 2u);
  const FaultId id = r.engage("unplug", 1);
  auto twice = r.faults.engage(FaultRequest{"unplug", 1, std::nullopt, {}});
  ASSERT_FALSE(twice);
  EXPECT_EQ(twice.error(), "unplug: already unplugged (fault 1)");
  auto power = r.faults.engage(FaultRequest{"power_cycle", 1, std::nullopt, {}});
  ASSERT_FALSE(power);
  EXPECT_EQ(power.error(), "power_cycle: slave 1 is unplugged (fault 1): plug it back first");
  ASSERT_TRUE(r.faults.clear(id));
  const FaultId off = r.engage("power_cycle", 1);
  auto pulled = r.faults.engage(FaultRequest{"unplug", 1, std::nullopt, {}});
  ASSERT_FALSE(pulled);
  EXPECT_EQ(pulled.error(), "unplug: slave 1 is powered off (fault 2)");
  ASSERT_TRUE(r.faults.clear(off));
  EXPECT_EQ(r.master.count_slaves().value_or(0), 2u);
}

}  // namespace
}  // namespace ecat::test
