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

// The ESC keeps the timeouts of 0x0400/0x0410/0x0420 (Watchdogs::set_times):
// every way of writing them reaches the next trigger - one byte at a time,
// the divider, the PDI time, a raw poke - and a running watchdog keeps the
// deadline of its last trigger.
TEST_F(WdTest, TriggersTakeTheTimesAsLastWritten) {
  write_outputs(0ms);  // 10 units of 100 µs
  EXPECT_EQ(esc().poll(0ms), 1ms);
  transact(seg(), Command::Fpwr, fp(kStation, reg::kWatchdogTimeProcessData), Data{20}, 500us);  // low byte only
  EXPECT_EQ(esc().poll(500us), 1ms);  // running: its deadline stays
  write_outputs(800us);
  EXPECT_EQ(esc().poll(800us), 2800us);  // 20 units
  // Divider 4998: (4998 + 2) x 40 ns = 200 µs a unit.
  transact(seg(), Command::Fpwr, fp(kStation, reg::kWatchdogDivider), le16(4998), 900us);
  write_outputs(1ms);
  EXPECT_EQ(esc().poll(1ms), 5ms);
  transact(seg(), Command::Fpwr, fp(kStation, reg::kWatchdogTimeProcessData + 1), Data{0x01}, 1100us);  // high byte
  write_outputs(2ms);
  EXPECT_EQ(esc().poll(2ms), 2ms + 0x0114 * 200us);
  // The PDI watchdog: 5 units = 1 ms from the PDI access.
  transact(seg(), Command::Fpwr, fp(kStation, reg::kWatchdogTimePdi), le16(5), 2ms);
  at(3ms);
  (void)esc().read_u16(reg::kAlControl);
  EXPECT_EQ(esc().poll(3ms), 4ms);
  esc().poll(4ms);
  EXPECT_EQ(esc().register_u16(reg::kDlStatus) & bits::kDlPdiWatchdogOk, 0);
  EXPECT_EQ(esc().memory()[reg::kWatchdogCounterPdi], 1);
  // A raw poke (fault injection) of the process-data time and of its
  // status: the next trigger takes the time and shows the status again.
  esc().poke_registers(reg::kWatchdogTimeProcessData, le16(3));
  esc().poke_registers(reg::kWatchdogStatusProcessData, Data{0});
  write_outputs(5ms);
  EXPECT_EQ(esc().poll(5ms), 5600us);
  EXPECT_EQ(esc().memory()[reg::kWatchdogStatusProcessData], 1);
  // Time 0 written while running: the deadline stays, the next trigger disables it.
  transact(seg(), Command::Fpwr, fp(kStation, reg::kWatchdogTimeProcessData), le16(0), 5100us);
  EXPECT_EQ(esc().poll(5100us), 5600us);
  write_outputs(5200us);
  EXPECT_EQ(esc().poll(5200us), std::nullopt);
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

// A firmware run's accesses take one time (Esc::pin_pdi_time): the clock's
// at the pin, however it moves before the unpin; the PDI watchdog counts
// from there. Unpinned, each access takes the clock's time again.
TEST_F(WdTest, PinnedPdiAccessesTakeTheTimeOfThePin) {
  at(1s);
  esc().pin_pdi_time();
  at(1s + 30ms);
  (void)esc().read_u16(reg::kAlControl);
  std::uint8_t outputs[4]{};
  (void)esc().read_buffer(kOutputs, outputs);  // SM2, in place
  esc().unpin_pdi_time();
  EXPECT_EQ(esc().poll(1s + 30ms), 1s + 100ms);
  esc().poll(1s + 100ms - 1ns);
  EXPECT_EQ(esc().register_u16(reg::kDlStatus) & bits::kDlPdiWatchdogOk, bits::kDlPdiWatchdogOk);
  esc().poll(1s + 100ms);
  EXPECT_EQ(esc().register_u16(reg::kDlStatus) & bits::kDlPdiWatchdogOk, 0);
  EXPECT_EQ(esc().memory()[reg::kWatchdogCounterPdi], 1);
  at(2s);
  (void)esc().read_u16(reg::kAlControl);
  at(2s + 30ms);
  (void)esc().read_u16(reg::kAlControl);
  EXPECT_EQ(esc().poll(2s + 30ms), 2s + 130ms);
}

// Section II 0x0802: an SM of length 1 is not activated ("shall be greater
// 1"), but an ECAT write to its byte still triggers the watchdog if control
// bit 6 is set - by FPWR, through a byte FMMU (routed LWR) and through a
// bit-granular FMMU (general path); also at the digital outputs 0x0F00.
struct OneByteWdTest : ::testing::Test {
  static constexpr std::uint16_t kOneByte = 0x1100;
  static constexpr std::uint32_t kLogical = 0x00020000;
  static constexpr std::uint8_t kFmmuWrite = 2;
  OneByteWdTest() : line(1) {
    assign_stations(line);
    transact(seg(), Command::Fpwr, fp(kStation, reg::kWatchdogTimeProcessData), le16(10));  // 1 ms
  }
  Line line;
  Esc& esc() { return line[0]; }
  Segment& seg() { return line.segment; }
  // Triggered at `t`: status 1 until t + 1 ms - 1 ns, 0 (counter 1) at t + 1 ms.
  void expect_expiry_after(Nanoseconds t) {
    EXPECT_EQ(esc().poll(t), t + 1ms);
    EXPECT_EQ(esc().memory()[reg::kWatchdogStatusProcessData], 1);
    esc().poll(t + 1ms - 1ns);
    EXPECT_EQ(esc().memory()[reg::kWatchdogStatusProcessData], 1);
    esc().poll(t + 1ms);
    EXPECT_EQ(esc().memory()[reg::kWatchdogStatusProcessData], 0);
    EXPECT_EQ(esc().memory()[reg::kWatchdogCounterProcessData], 1);
    EXPECT_EQ(esc().memory()[reg::kAlEventRequest] & bits::kAlEventWatchdog, bits::kAlEventWatchdog);
  }
};

TEST_F(OneByteWdTest, FpwrTriggers) {
  config_sm(seg(), kStation, 2, kOneByte, 1, 0x64);
  EXPECT_EQ(esc().poll(0ms), std::nullopt);
  EXPECT_EQ(transact(seg(), Command::Fpwr, fp(kStation, kOneByte), Data{0x5A}, 2ms).wkc, 1);
  EXPECT_EQ(esc().memory()[kOneByte], 0x5A);  // not buffered: written in place
  expect_expiry_after(2ms);
}

TEST_F(OneByteWdTest, RoutedLwrTriggers) {
  config_sm(seg(), kStation, 2, kOneByte, 1, 0x64);
  config_fmmu(seg(), kStation, 0, kLogical, 1, 0, 7, kOneByte, 0, kFmmuWrite);
  EXPECT_EQ(transact(seg(), Command::Lwr, kLogical, Data{0x11}, 3ms).wkc, 1);
  expect_expiry_after(3ms);
}

// A byte FMMU over four bytes of plain RAM, the last of them a 1-byte SM:
// an LWR that writes only the first two does not restart the watchdog (the
// bytes written, not the FMMU, decide, as for an FPWR); one that reaches
// the SM's byte does.
TEST_F(OneByteWdTest, RoutedLwrTriggersOnlyWhenItWritesTheSmByte) {
  config_sm(seg(), kStation, 2, kOneByte + 3, 1, 0x64);
  config_fmmu(seg(), kStation, 0, kLogical, 4, 0, 7, kOneByte, 0, kFmmuWrite);
  EXPECT_EQ(transact(seg(), Command::Lwr, kLogical, Data{0x11, 0x22}, 3ms).wkc, 1);
  EXPECT_EQ(esc().memory()[kOneByte + 1], 0x22);
  EXPECT_EQ(esc().poll(3ms), std::nullopt);
  EXPECT_EQ(esc().memory()[reg::kWatchdogStatusProcessData], 1);
  EXPECT_EQ(transact(seg(), Command::Lwr, kLogical + 2, Data{0x33, 0x44}, 4ms).wkc, 1);
  EXPECT_EQ(esc().memory()[kOneByte + 3], 0x44);
  expect_expiry_after(4ms);
}

// The same route over two 1-byte SMs (bytes 1 and 3): the bytes between
// and around them do not restart the watchdog, either SM's byte does.
TEST_F(OneByteWdTest, RoutedLwrOverTwoSmBytesTriggersAtEither) {
  config_sm(seg(), kStation, 2, kOneByte + 1, 1, 0x64);
  config_sm(seg(), kStation, 3, kOneByte + 3, 1, 0x64);
  config_fmmu(seg(), kStation, 0, kLogical, 4, 0, 7, kOneByte, 0, kFmmuWrite);
  EXPECT_EQ(transact(seg(), Command::Lwr, kLogical, Data{0x11}, 3ms).wkc, 1);
  EXPECT_EQ(transact(seg(), Command::Lwr, kLogical + 2, Data{0x33}, 3ms).wkc, 1);
  EXPECT_EQ(esc().memory()[kOneByte + 2], 0x33);
  EXPECT_EQ(esc().poll(3ms), std::nullopt);
  EXPECT_EQ(transact(seg(), Command::Lwr, kLogical + 3, Data{0x44}, 4ms).wkc, 1);
  expect_expiry_after(4ms);
  EXPECT_EQ(transact(seg(), Command::Lwr, kLogical + 1, Data{0x22}, 6ms).wkc, 1);
  EXPECT_EQ(esc().poll(6ms), 7ms);
}

// ESC write protection (0x0031) keeps the byte as it was, but the write
// still restarts the watchdog - through an FMMU as by FPWR (mem_write
// restarts it before it looks at the protection).
TEST_F(OneByteWdTest, ProtectedRamKeepsItsByteAndTheLwrStillTriggers) {
  config_sm(seg(), kStation, 2, kOneByte, 1, 0x64);
  config_fmmu(seg(), kStation, 0, kLogical, 1, 0, 7, kOneByte, 0, kFmmuWrite);
  transact(seg(), Command::Fpwr, fp(kStation, reg::kEscWriteProtection), Data{0x01});
  EXPECT_EQ(transact(seg(), Command::Lwr, kLogical, Data{0x11}, 3ms).wkc, 0);
  EXPECT_EQ(esc().memory()[kOneByte], 0x00);
  expect_expiry_after(3ms);
  EXPECT_EQ(transact(seg(), Command::Fpwr, fp(kStation, kOneByte), Data{0x22}, 5ms).wkc, 0);
  EXPECT_EQ(esc().poll(5ms), 6ms);
}

TEST_F(OneByteWdTest, BitGranularLwrTriggers) {
  config_sm(seg(), kStation, 2, kOneByte, 1, 0x64);
  config_fmmu(seg(), kStation, 0, kLogical, 1, 0, 3, kOneByte, 0, kFmmuWrite);  // 4 bits
  EXPECT_EQ(transact(seg(), Command::Lwr, kLogical, Data{0xFF}, 4ms).wkc, 1);
  EXPECT_EQ(esc().memory()[kOneByte], 0x0F);
  expect_expiry_after(4ms);
}

TEST_F(OneByteWdTest, DigitalOutputRegisterTriggers) {
  config_sm(seg(), kStation, 0, reg::kDigitalIoOutput, 1, 0x44);  // EL2004-style: 0x0F00, length 1
  EXPECT_EQ(transact(seg(), Command::Fpwr, fp(kStation, reg::kDigitalIoOutput), Data{0x03}, 5ms).wkc, 1);
  expect_expiry_after(5ms);
  EXPECT_EQ(esc().memory()[reg::kDigitalIoOutput], 0x00);  // outputs to 0 on expiry
}

// An SM of more than one byte over the digital output registers (an EL9800
// revision of beckhoff-ethercat-evaboard.xml: SM0 0F00h, 4 bytes, control
// 46h = mailbox mode, ECAT writes, watchdog trigger): the bytes are the
// registers, and an ECAT write to any of them - by FPWR or through an FMMU -
// restarts the watchdog (issue 14).
TEST_F(OneByteWdTest, FourByteSmOverTheDigitalOutputsTriggers) {
  config_sm(seg(), kStation, 0, reg::kDigitalIoOutput, 4, 0x46);
  EXPECT_EQ(transact(seg(), Command::Fpwr, fp(kStation, reg::kDigitalIoOutput + 2), Data{0x81}, 5ms).wkc, 1);
  EXPECT_EQ(esc().memory()[reg::kDigitalIoOutput + 2], 0x81);
  expect_expiry_after(5ms);
  EXPECT_EQ(esc().memory()[reg::kDigitalIoOutput + 2], 0x00);  // outputs to 0 on expiry
  config_fmmu(seg(), kStation, 0, kLogical, 4, 0, 7, reg::kDigitalIoOutput, 0, kFmmuWrite);
  EXPECT_EQ(transact(seg(), Command::Lwr, kLogical, Data{1, 2, 3, 4}, 8ms).wkc, 1);
  EXPECT_EQ(esc().memory()[reg::kDigitalIoOutput + 3], 0x04);
  EXPECT_EQ(esc().poll(8ms), 9ms);
  EXPECT_EQ(esc().memory()[reg::kWatchdogStatusProcessData], 1);
}

TEST_F(OneByteWdTest, NoTriggerWithoutBit6OrEnableOrWhenReadDirection) {
  config_sm(seg(), kStation, 2, kOneByte, 1, 0x24);  // no trigger bit
  config_sm(seg(), kStation, 3, 0x1101, 1, 0x64, 0);  // not enabled
  config_sm(seg(), kStation, 4, 0x1102, 1, 0x60);  // ECAT reads
  transact(seg(), Command::Fpwr, fp(kStation, kOneByte), Data{1, 2, 3}, 1ms);
  EXPECT_EQ(esc().poll(1ms), std::nullopt);
  EXPECT_EQ(esc().memory()[reg::kWatchdogStatusProcessData], 1);
}

}  // namespace
}  // namespace ecat::esc::test
