// The firmware runs on its ESC's IRQ (AL event request & the mask it
// programs in 0x0204) or its own deadline, not after every frame (issue 8):
// the mask it keeps per state and sync mode, frames that raise no event
// leaving it asleep, an AL control request served on the frame that
// carries it, a mask restored after an ESC reset, and the returned-frame
// tally of ChainStats.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>

#include "common/frame_builder.hpp"
#include "common/le.hpp"
#include "esc/registers.hpp"
#include "slave/firmware.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

// AL event request bits (ESC datasheet Section II 0x0220).
constexpr std::uint32_t kAlControl = 1u << 0;
constexpr std::uint32_t kSmActivation = 1u << 4;
constexpr std::uint32_t kWatchdog = 1u << 6;
constexpr std::uint32_t kSm0 = 1u << 8;
constexpr std::uint32_t kSm1 = 1u << 9;
constexpr std::uint32_t kSm2 = 1u << 10;
constexpr std::uint32_t kSync0 = 1u << 2;
constexpr std::uint32_t kAlwaysHandled = kAlControl | kSmActivation | kWatchdog | kSm0 | kSm1;
constexpr std::uint16_t kAlStatePreOp = 2;
constexpr std::uint16_t kAlStateOp = 8;
constexpr std::uint16_t kEscResetEcat = 0x0040;
constexpr std::array<std::uint8_t, 3> kResetSequence{'R', 'E', 'S'};

std::uint32_t mask_in_esc(slave::VirtualSlave& s) {
  return load_le<std::uint32_t>(s.esc().memory() + esc::reg::kAlEventMask);
}
std::uint64_t polls(slave::VirtualSlave& s) { return s.firmware().status().firmware_polls; }

// Lets time pass until no firmware deadline falls in the next `margin`, so
// the frames that follow meet none (free run: the next cycle is 1 ms away).
void clear_deadlines(InProcess& p, Nanoseconds margin) {
  for (std::size_t i = 0; i < p.chain.size(); ++i) {
    const auto next = p.chain[i].firmware().next_deadline();
    if (next && *next <= p.clock.now() + margin) p.advance(*next - p.clock.now());
  }
  for (std::size_t i = 0; i < p.chain.size(); ++i) {
    const auto next = p.chain[i].firmware().next_deadline();
    if (next) {
      ASSERT_GT(*next, p.clock.now() + margin) << "slave " << i;
    }
  }
}

TEST(FirmwareEvents, MaskInInitCoversStateMachineAndMailbox) {
  InProcess p;
  p.add_default(1);
  EXPECT_EQ(mask_in_esc(p.chain[0]), kAlwaysHandled);
  EXPECT_EQ(p.chain[0].firmware().event_mask(), kAlwaysHandled);
}

TEST(FirmwareEvents, MaskInOpAddsWhatTheSyncModeWaitsFor) {
  InProcess p;
  p.add_default(2);
  ASSERT_EQ(p.bring_up(), "");
  for (std::size_t i = 0; i < 2; ++i) {
    const coe::SyncMode mode = p.chain[i].firmware().sync().output_mode();
    std::uint32_t want = kAlwaysHandled;
    if (mode == coe::SyncMode::SmSynchronous || mode == coe::SyncMode::SmSynchronousSm2) want |= kSm2;
    if (mode == coe::SyncMode::DcSync0) want |= kSync0 | kSm2;
    EXPECT_EQ(mask_in_esc(p.chain[i]), want) << "slave " << i << " mode " << static_cast<int>(mode);
  }
}

TEST(FirmwareEvents, FramesWithoutEventsLeaveTheFirmwareAsleep) {
  InProcess p;
  p.add_default(2);
  ASSERT_EQ(p.bring_up(), "");
  clear_deadlines(p, std::chrono::microseconds(100));
  const std::uint64_t before0 = polls(p.chain[0]);
  const std::uint64_t before1 = polls(p.chain[1]);
  for (int k = 0; k < 5; ++k) {
    auto st = p.master.read_al_status(0);
    ASSERT_TRUE(st);
  }
  EXPECT_EQ(polls(p.chain[0]), before0);
  EXPECT_EQ(polls(p.chain[1]), before1);
}

TEST(FirmwareEvents, AlControlIsServedOnTheFrameThatWritesIt) {
  InProcess p;
  p.add_default(2);
  ASSERT_EQ(p.bring_up(), "");
  clear_deadlines(p, std::chrono::microseconds(100));
  const std::uint64_t before1 = polls(p.chain[1]);
  // One FPWR to slave 0's AL control, no Chain::poll: its IRQ runs the ESM.
  ASSERT_TRUE(p.master.fpwr_u16(p.master.slave(0).station_address, esc::reg::kAlControl, kAlStatePreOp));
  EXPECT_EQ(p.chain[0].firmware().esm().state(), esc::AlState::PreOp);
  EXPECT_EQ(p.chain[0].esc().register_u16(esc::reg::kAlStatus), kAlStatePreOp);
  EXPECT_EQ(p.chain[1].firmware().esm().state(), esc::AlState::Op);
  EXPECT_EQ(polls(p.chain[1]), before1);
  // PreOp waits for nothing cyclic: the mask is back to the base set.
  EXPECT_EQ(mask_in_esc(p.chain[0]), kAlwaysHandled);
}

// Chain::pass_frame is the ESCs' part only (what a live wire sends back at
// once); the firmware answers the AL control request in run_firmware().
TEST(FirmwareEvents, PassFrameLeavesTheFirmwareToRunFirmware) {
  InProcess p;
  p.add_default(1);
  ASSERT_EQ(p.bring_up(), "");
  clear_deadlines(p, std::chrono::microseconds(100));
  std::array<std::uint8_t, kMinEthernetFrame> buffer{};
  FrameBuilder b(buffer, kBroadcastMac, MacAddress{0x02, 0, 0, 0, 0, 1});
  std::array<std::uint8_t, 2> pre_op{};
  store_le(pre_op.data(), kAlStatePreOp);
  const auto at = b.append(Command::Fpwr, 0, device_address(p.master.slave(0).station_address, esc::reg::kAlControl),
                           pre_op);
  ASSERT_TRUE(at);
  auto frame = b.finish();
  const std::uint64_t before = polls(p.chain[0]);
  ASSERT_TRUE(p.chain.pass_frame(frame, p.clock.now()));
  EXPECT_EQ(load_le<std::uint16_t>(frame.data() + *at + kDatagramHeaderSize + pre_op.size()), 1u);  // WKC
  EXPECT_EQ(polls(p.chain[0]), before);
  EXPECT_EQ(p.chain[0].esc().register_u16(esc::reg::kAlStatus), kAlStateOp);
  p.chain.run_firmware(p.clock.now());
  EXPECT_EQ(polls(p.chain[0]), before + 1);
  EXPECT_EQ(p.chain[0].esc().register_u16(esc::reg::kAlStatus), kAlStatePreOp);
}

// The check a chain makes after every frame (Firmware::may_want_poll, a
// few loads) must be true whenever wants_poll() is: through bring-up,
// cyclic exchange, mailbox traffic, state changes and time between frames.
TEST(FirmwareEvents, CheapCheckAfterEachFrameCoversEveryReasonToPoll) {
  InProcess p;
  p.add_default(2);
  auto covered = [&](const char* what) {
    for (std::size_t i = 0; i < p.chain.size(); ++i) {
      const slave::Firmware& fw = p.chain[i].firmware();
      const slave::EscLines lines = p.chain[i].lines();
      for (const Nanoseconds later : {Nanoseconds{0}, Nanoseconds{500'000}, Nanoseconds{1'000'000},
                                      Nanoseconds{3'000'000}}) {
        const Nanoseconds t = p.clock.now() + later;
        if (fw.wants_poll(t, lines)) {
          ASSERT_TRUE(fw.may_want_poll(t, lines)) << what << ": slave " << i << " at +" << later.count() << " ns";
        }
      }
    }
  };
  ASSERT_NO_FATAL_FAILURE(covered("power-on"));
  ASSERT_EQ(p.bring_up(), "");
  ASSERT_NO_FATAL_FAILURE(covered("Op"));
  for (int c = 0; c < 20; ++c) {
    ASSERT_TRUE(p.cycle_once(std::chrono::microseconds(250 * (c % 5 + 1))));
    ASSERT_NO_FATAL_FAILURE(covered("cycle"));
    if (c % 7 == 3) {
      master::CoeClient coe(p.master, static_cast<std::size_t>(c % 2));
      ASSERT_TRUE(coe.upload_value(0x1018, 1));
      ASSERT_NO_FATAL_FAILURE(covered("SDO upload"));
    }
  }
  ASSERT_TRUE(p.master.fpwr_u16(p.master.slave(1).station_address, esc::reg::kAlControl, kAlStatePreOp));
  ASSERT_NO_FATAL_FAILURE(covered("PreOp request"));
  for (int c = 0; c < 5; ++c) {
    ASSERT_TRUE(p.cycle_once(std::chrono::milliseconds(1)));
    ASSERT_NO_FATAL_FAILURE(covered("cycle after PreOp"));
  }
}

TEST(FirmwareEvents, MaskIsRestoredAfterAnEscReset) {
  InProcess p;
  p.add_default(1);
  const std::uint16_t station = 0;  // before the scan: position 0 by APWR
  for (std::uint8_t c : kResetSequence) {
    std::array<std::uint8_t, 1> b{c};
    ASSERT_TRUE(p.master.transact(Command::Apwr, device_address(station, kEscResetEcat), b));
  }
  // The reset cleared 0x0204; the firmware saw it at the next frame.
  EXPECT_EQ(mask_in_esc(p.chain[0]), kAlwaysHandled);
}

TEST(FirmwareEvents, ReturnedFramesAreTalliedByDatagramAndWkc) {
  InProcess p;
  p.add_default(3);
  ASSERT_TRUE(p.master.scan());
  const slave::ChainStats before = p.chain.stats();
  std::array<std::uint8_t, 2> b{};
  auto wkc = p.master.transact(Command::Brd, device_address(0, esc::reg::kAlStatus), b);
  ASSERT_TRUE(wkc);
  EXPECT_EQ(*wkc, 3);
  ASSERT_TRUE(p.master.fprd_u16(p.master.slave(1).station_address, esc::reg::kAlStatus));
  EXPECT_EQ(p.chain.stats().frames_returned - before.frames_returned, 2u);
  EXPECT_EQ(p.chain.stats().datagrams - before.datagrams, 2u);
  EXPECT_EQ(p.chain.stats().wkc_total - before.wkc_total, 3u + 1u);
}

}  // namespace
}  // namespace ecat::test
