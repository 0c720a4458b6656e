// Process-data and PDI watchdogs on injected time (Section II 0x0400-0x0443).
#include <gtest/gtest.h>

#include "esc/register_bits.hpp"
#include "esc_fixture.hpp"

namespace ecat::esc::test {
namespace {

constexpr std::uint16_t kStation = 0x1001;
constexpr std::uint16_t kOutputs = 0x1100;

TEST(WatchdogTiming, DividerAndTime) {
  // Reset values: (2498 + 2) x 40 ns = 100 µs unit, x 1000 = 100 ms.
  EXPECT_EQ(Watchdogs::timeout(kWatchdogDividerReset, kWatchdogTimeReset), 100ms);
  EXPECT_EQ(Watchdogs::timeout(0, 1), 80ns);
  EXPECT_EQ(Watchdogs::timeout(kWatchdogDividerReset, 0), 0ns);
}

struct WdTest : ::testing::Test {
  WdTest() : line(1) {
    assign_stations(line);
    config_sm(seg(), kStation, 2, kOutputs, 4, 0x64);  // outputs with watchdog trigger
    transact(seg(), Command::Fpwr, fp(kStation, reg::kWatchdogTimeProcessData), le16(10));  // 1 ms
  }
  Line line;
  Esc& esc() { return line[0]; }
  Segment& seg() { return line.segment; }
  void at(Nanoseconds t) { line.clock.set(t); }
  Reply write_outputs(Nanoseconds t) {
    at(t);
    return transact(seg(), Command::Fpwr, fp(kStation, kOutputs), Data{1, 2, 3, 4}, t);
  }
};

TEST_F(WdTest, ProcessDataWatchdogExpiresOnTime) {
  // Not running before the first trigger.
  EXPECT_EQ(esc().poll(50ms), std::nullopt);
  EXPECT_EQ(esc().memory()[reg::kWatchdogStatusProcessData], 1);
  transact(seg(), Command::Fpwr, fp(kStation, reg::kDigitalIoOutput), Data{0xFF}, 50ms);
  EXPECT_EQ(write_outputs(50ms).wkc, 1);
  EXPECT_EQ(esc().poll(50ms), 51ms);
  EXPECT_EQ(esc().poll(51ms - 1ns), 51ms);
  EXPECT_EQ(esc().memory()[reg::kWatchdogStatusProcessData], 1);
  esc().poll(51ms);
  EXPECT_EQ(esc().memory()[reg::kWatchdogStatusProcessData], 0);
  EXPECT_EQ(esc().memory()[reg::kWatchdogCounterProcessData], 1);
  EXPECT_EQ(esc().memory()[reg::kDigitalIoOutput], 0x00);  // outputs to 0
  EXPECT_EQ(esc().memory()[reg::kAlEventRequest] & bits::kAlEventWatchdog, bits::kAlEventWatchdog);
  // Expires once; the PDI reading 0x0440 acknowledges the AL event.
  esc().poll(60ms);
  EXPECT_EQ(esc().memory()[reg::kWatchdogCounterProcessData], 1);
  at(60ms);
  EXPECT_EQ(esc().read_u8(reg::kWatchdogStatusProcessData), 0);
  EXPECT_EQ(esc().memory()[reg::kAlEventRequest] & bits::kAlEventWatchdog, 0);
  // A new trigger re-arms it.
  write_outputs(61ms);
  EXPECT_EQ(esc().memory()[reg::kWatchdogStatusProcessData], 1);
  write_outputs(61ms + 900us);
  esc().poll(62ms);
  EXPECT_EQ(esc().memory()[reg::kWatchdogStatusProcessData], 1);
  // Checked on frame arrival too, not only in poll().
  auto r = transact(seg(), Command::Fprd, fp(kStation, reg::kWatchdogStatusProcessData), 4, 63ms);
  EXPECT_EQ(r.data, (Data{0, 0, 2, 0}));
  // ECAT writing 0x0442 clears both counters.
  transact(seg(), Command::Fpwr, fp(kStation, reg::kWatchdogCounterProcessData), Data{0}, 63ms);
  EXPECT_EQ(esc().memory()[reg::kWatchdogCounterProcessData], 0);
}

TEST_F(WdTest, OnlyTriggeringSmsRestartIt) {
  config_sm(seg(), kStation, 3, 0x1200, 4, 0x20);  // inputs, no trigger bit
  write_outputs(0ms);
  transact(seg(), Command::Fpwr, fp(kStation, 0x1200), Data{0, 0, 0, 0}, 900us);  // wrong direction anyway
  transact(seg(), Command::Fpwr, fp(kStation, 0x1300), Data{0}, 900us);  // plain RAM
  esc().poll(1ms);
  EXPECT_EQ(esc().memory()[reg::kWatchdogStatusProcessData], 0);
}

TEST_F(WdTest, ZeroTimeDisables) {
  transact(seg(), Command::Fpwr, fp(kStation, reg::kWatchdogTimeProcessData), le16(0));
  write_outputs(0ms);
  EXPECT_EQ(esc().poll(10s), std::nullopt);
  EXPECT_EQ(esc().memory()[reg::kWatchdogStatusProcessData], 1);
}

TEST_F(WdTest, PdiWatchdog) {
  at(1s);
  (void)esc().read_u16(reg::kAlControl);  // PDI access at 1 s starts it (100 ms default)
  EXPECT_EQ(esc().register_u16(reg::kDlStatus) & bits::kDlPdiWatchdogOk, bits::kDlPdiWatchdogOk);
  esc().poll(1s + 99ms);
  EXPECT_EQ(esc().register_u16(reg::kDlStatus) & bits::kDlPdiWatchdogOk, bits::kDlPdiWatchdogOk);
  esc().poll(1s + 100ms);
  EXPECT_EQ(esc().register_u16(reg::kDlStatus) & bits::kDlPdiWatchdogOk, 0);
  EXPECT_EQ(esc().memory()[reg::kWatchdogCounterPdi], 1);
  at(2s);
  esc().write_u16(reg::kAlStatusCode, 0);
  EXPECT_EQ(esc().register_u16(reg::kDlStatus) & bits::kDlPdiWatchdogOk, bits::kDlPdiWatchdogOk);
}

}  // namespace
}  // namespace ecat::esc::test
