// Esc::pdi_attention() / irq(): every EtherCAT-side event the application
// must react to sets its AL event request bit (Section II 0x0220; shared/
// spec/esc-registers.md §4.10, §5), including on the fast LRW route, and the
// application's acknowledgement clears it. A host may run only the firmware
// of slaves with attention after a frame.
#include <gtest/gtest.h>

#include "esc_fixture.hpp"

namespace ecat::esc::test {
namespace {

constexpr std::uint16_t kStation = 0x1001;
constexpr std::uint16_t kOutputs = 0x1100;
constexpr std::uint16_t kInputs = 0x1200;
constexpr std::uint16_t kBytes = 4;
constexpr std::uint8_t kSmOutputs = 0x64;  // 3-buffer, ECAT writes, AL event, watchdog trigger
constexpr std::uint8_t kSmInputs = 0x20;   // 3-buffer, ECAT reads, AL event
constexpr std::uint8_t kSmNoAlEvent = 0x44;  // 3-buffer, ECAT writes, watchdog trigger only

class AttentionTest : public testing::Test {
 protected:
  AttentionTest() : line(1) { assign_stations(line); }
  Esc& esc() { return line[0]; }
  std::uint32_t al_event() {
    std::uint8_t b[4]{};
    esc().read(reg::kAlEventRequest, b);
    return load_le<std::uint32_t>(b);
  }
  void map(std::uint8_t out_control) {
    config_sm(line.segment, kStation, 2, kOutputs, kBytes, out_control);
    config_sm(line.segment, kStation, 3, kInputs, kBytes, kSmInputs);
    config_fmmu(line.segment, kStation, 0, 0, kBytes, 0, 7, kOutputs, 0, 2);
    config_fmmu(line.segment, kStation, 1, kBytes, kBytes, 0, 7, kInputs, 0, 1);
    // Acknowledge the activation event (PDI reads the activate registers).
    std::uint8_t b = 0;
    esc().read(static_cast<std::uint16_t>(reg::sync_manager(2) + reg::sm::kActivate), std::span(&b, 1));
  }
  Line line;
};

TEST_F(AttentionTest, QuietAfterResetAndPlainAccesses) {
  EXPECT_FALSE(esc().pdi_attention());
  transact(line.segment, Command::Fprd, fp(kStation, reg::kAlStatus), 2);
  transact(line.segment, Command::Fpwr, fp(kStation, reg::kWatchdogDivider), le16(0x09C2));
  transact(line.segment, Command::Fpwr, fp(kStation, 0x1800), le32(0x12345678));
  EXPECT_FALSE(esc().pdi_attention());
  EXPECT_FALSE(esc().irq());
  EXPECT_EQ(esc().next_timer(), Nanoseconds::max());
}

TEST_F(AttentionTest, AlControlWriteUntilThePdiReadsIt) {
  transact(line.segment, Command::Fpwr, fp(kStation, reg::kAlControl), le16(0x0002));
  EXPECT_TRUE(esc().pdi_attention());
  EXPECT_EQ(al_event(), bits::kAlEventAlControl);
  EXPECT_FALSE(esc().irq());  // the mask is 0 after reset
  esc().write(reg::kAlEventMask, le32(bits::kAlEventAlControl));
  EXPECT_TRUE(esc().irq());
  std::uint8_t b[2]{};
  esc().read(reg::kAlControl, b);
  EXPECT_FALSE(esc().pdi_attention());
  EXPECT_FALSE(esc().irq());
}

TEST_F(AttentionTest, SmActivationChange) {
  transact(line.segment, Command::Fpwr, fp(kStation, reg::sync_manager(1) + reg::sm::kActivate), Data{0x02});
  EXPECT_EQ(al_event(), bits::kAlEventSmActivation);
  std::uint8_t b = 0;
  esc().read(static_cast<std::uint16_t>(reg::sync_manager(1) + reg::sm::kActivate), std::span(&b, 1));
  EXPECT_FALSE(esc().pdi_attention());
}

TEST_F(AttentionTest, LrwThroughTheSmRouteRaisesTheSmEvents) {
  map(kSmOutputs);
  ASSERT_FALSE(esc().pdi_attention());
  TestFrame f;
  f.add(Command::Lrw, 0, Data{1, 2, 3, 4, 0, 0, 0, 0});
  ASSERT_TRUE(f.send(line.segment));
  EXPECT_EQ(f.wkc(0), 3);
  // SM2 written (bit 10), SM3 read (bit 11): both buffers changed hands.
  const std::uint32_t sm2 = 1u << (bits::kAlEventSmShift + 2);
  const std::uint32_t sm3 = 1u << (bits::kAlEventSmShift + 3);
  EXPECT_EQ(al_event(), sm2 | sm3);
  esc().write(reg::kAlEventMask, le32(sm2));
  EXPECT_TRUE(esc().irq());
  // The process-data watchdog now runs: its deadline is the next timer.
  EXPECT_EQ(esc().next_timer(), Watchdogs::timeout(kWatchdogDividerReset, kWatchdogTimeReset));
  // The application takes the outputs and writes the inputs: both acknowledged.
  std::uint8_t out[kBytes]{};
  esc().read(kOutputs, out);
  EXPECT_EQ(out[3], 4);
  esc().write(kInputs, Data{9, 9, 9, 9});
  EXPECT_FALSE(esc().pdi_attention());
}

TEST_F(AttentionTest, NoEventWithoutSmControlBit5) {
  map(kSmNoAlEvent);
  TestFrame f;
  f.add(Command::Lwr, 0, Data{1, 2, 3, 4});
  ASSERT_TRUE(f.send(line.segment));
  EXPECT_EQ(f.wkc(0), 1);
  EXPECT_FALSE(esc().pdi_attention());
}

TEST_F(AttentionTest, ProcessDataWatchdogExpiry) {
  map(kSmOutputs);
  TestFrame f;
  f.add(Command::Lwr, 0, Data{1, 2, 3, 4});
  ASSERT_TRUE(f.send(line.segment));
  std::uint8_t out[kBytes]{};
  esc().read(kOutputs, out);  // acknowledge SM2
  ASSERT_FALSE(esc().pdi_attention());
  const Nanoseconds expiry = esc().next_timer();
  ASSERT_EQ(expiry, Watchdogs::timeout(kWatchdogDividerReset, kWatchdogTimeReset));
  // A frame just before the deadline leaves it armed; one at it expires it.
  TestFrame before;
  before.add(Command::Brd, device_address(0, reg::kAlStatus), 2);
  ASSERT_TRUE(before.send(line.segment, expiry - Nanoseconds{1}));
  EXPECT_FALSE(esc().pdi_attention());
  TestFrame at;
  at.add(Command::Brd, device_address(0, reg::kAlStatus), 2);
  ASSERT_TRUE(at.send(line.segment, expiry));
  EXPECT_EQ(esc().memory()[reg::kAlEventRequest], bits::kAlEventWatchdog);
  EXPECT_TRUE(esc().pdi_attention());
  EXPECT_EQ(esc().next_timer(), Nanoseconds::max());
}

}  // namespace
}  // namespace ecat::esc::test
