// The ESM over the real emulated ESC, driven as a master drives it: datagrams
// through esc::Segment, AL status read back as 6 bytes from 0x0130 (status,
// reserved, code - as SOEM/TwinCAT read it; masters.md §6 #11).
#include <gtest/gtest.h>

#include <array>
#include <memory>

#include "esc/esm.hpp"
#include "esc_fixture.hpp"
#include "esm_fixture.hpp"

namespace ecat::esc::test {
namespace {

constexpr std::uint16_t kStation = 0x1001;

class EsmOverEscTest : public ::testing::Test {
 protected:
  EsmOverEscTest() : line(2) {
    assign_stations(line);
    for (std::size_t i = 0; i < 2; ++i) {
      esms[i] = std::make_unique<Esm>(line[i], test_esm_config());
      esms[i]->reset();
    }
  }
  void poll_slaves() {
    for (auto& e : esms) e->poll();
  }
  // FPWR 0x0120, the slaves poll, then FPRD 0x0130:6.
  Data request(std::uint16_t control, std::uint16_t station = kStation) {
    const Reply w = transact(line.segment, Command::Fpwr, fp(station, reg::kAlControl), le16(control), now());
    EXPECT_EQ(w.wkc, 1);
    poll_slaves();
    return al_status(station);
  }
  Data al_status(std::uint16_t station = kStation) {
    return transact(line.segment, Command::Fprd, fp(station, reg::kAlStatus), 6, now()).data;
  }
  void mailbox(std::uint16_t station = kStation, std::uint16_t sm0_length = kMbxLength) {
    config_sm(line.segment, station, 0, kMbxOutStart, sm0_length, kMbxOutControl);
    config_sm(line.segment, station, 1, kMbxInStart, kMbxLength, kMbxInControl);
  }
  void process(std::uint16_t station = kStation) {
    config_sm(line.segment, station, 2, kOutStart, 4, kOutControl);
    config_sm(line.segment, station, 3, kInStart, 6, kInControl);
  }
  Nanoseconds now() const { return line.clock.now(); }
  static Data status(std::uint16_t state, std::uint16_t code) {
    return Data{static_cast<std::uint8_t>(state), static_cast<std::uint8_t>(state >> 8), 0, 0,
                static_cast<std::uint8_t>(code), static_cast<std::uint8_t>(code >> 8)};
  }

  Line line;
  std::array<std::unique_ptr<Esm>, 2> esms;
};

TEST_F(EsmOverEscTest, EveryAllowedTransitionUpAndDown) {
  EXPECT_EQ(al_status(), status(0x0001, 0));
  mailbox();
  EXPECT_EQ(request(0x0002), status(0x0002, 0));
  process();
  EXPECT_EQ(request(0x0004), status(0x0004, 0));
  EXPECT_EQ(request(0x0008), status(0x0008, 0));
  EXPECT_EQ(request(0x0004), status(0x0004, 0));  // OS
  EXPECT_EQ(request(0x0002), status(0x0002, 0));  // SP
  EXPECT_EQ(request(0x0004), status(0x0004, 0));
  EXPECT_EQ(request(0x0001), status(0x0001, 0));  // SI
  EXPECT_EQ(request(0x0002), status(0x0002, 0));
  EXPECT_EQ(request(0x0001), status(0x0001, 0));  // PI
  EXPECT_EQ(request(0x0002), status(0x0002, 0));
  EXPECT_EQ(request(0x0004), status(0x0004, 0));
  EXPECT_EQ(request(0x0008), status(0x0008, 0));
  EXPECT_EQ(request(0x0002), status(0x0002, 0));  // OP
  EXPECT_EQ(request(0x0004), status(0x0004, 0));
  EXPECT_EQ(request(0x0008), status(0x0008, 0));
  EXPECT_EQ(request(0x0001), status(0x0001, 0));  // OI
  // The other slave never moved.
  EXPECT_EQ(al_status(kStation + 1), status(0x0001, 0));
}

TEST_F(EsmOverEscTest, ForbiddenTransitionsAndAcknowledge) {
  EXPECT_EQ(request(0x0004), status(0x0011, 0x0011));  // I->S
  EXPECT_EQ(request(0x0002), status(0x0011, 0x0011));  // ignored without ack
  EXPECT_EQ(request(0x0011), status(0x0001, 0));       // ack
  EXPECT_EQ(request(0x0008), status(0x0011, 0x0011));  // I->O
  EXPECT_EQ(request(0x0013), status(0x0011, 0x0013));  // ack + Boot: not supported
  EXPECT_EQ(request(0x0015), status(0x0011, 0x0012));  // ack + unknown state 5
  mailbox();
  EXPECT_EQ(request(0x0012), status(0x0002, 0));       // ack + PreOp
  EXPECT_EQ(request(0x0008), status(0x0012, 0x0011));  // P->O
  EXPECT_EQ(request(0x0013), status(0x0012, 0x0011));  // P->B
  EXPECT_EQ(request(0x0012), status(0x0002, 0));
  process();
  EXPECT_EQ(request(0x0004), status(0x0004, 0));
  EXPECT_EQ(request(0x0003), status(0x0014, 0x0011));  // S->B
  EXPECT_EQ(request(0x0018), status(0x0008, 0));       // ack + Op
  EXPECT_EQ(request(0x0003), status(0x0018, 0x0011));  // O->B
  EXPECT_EQ(request(0x0001), status(0x0001, 0));       // Init acknowledges too
}

TEST_F(EsmOverEscTest, WrongMailboxRefusedAndMailboxClosedInInit) {
  mailbox(kStation, 64);
  EXPECT_EQ(request(0x0002), status(0x0011, 0x0016));
  // SM0 is PDI-deactivated in Init: a master write into the mailbox gets no WKC.
  EXPECT_EQ(transact(line.segment, Command::Fpwr, fp(kStation, kMbxOutStart), Data(64, 0xAA), now()).wkc, 0);
  config_sm(line.segment, kStation, 0, 0, 0, 0, 0);  // masters disable before re-writing
  mailbox();
  EXPECT_EQ(request(0x0012), status(0x0002, 0));
  EXPECT_EQ(transact(line.segment, Command::Fpwr, fp(kStation, kMbxOutStart), Data(kMbxLength, 0xAA), now()).wkc, 1);
}

TEST_F(EsmOverEscTest, WrongProcessSmRefused) {
  mailbox();
  request(0x0002);
  config_sm(line.segment, kStation, 2, 0x1104, 4, kOutControl);
  config_sm(line.segment, kStation, 3, kInStart, 6, kInControl);
  EXPECT_EQ(request(0x0004), status(0x0012, 0x001D));
}

TEST_F(EsmOverEscTest, MailboxChangedInPreOpFallsToInit) {
  mailbox();
  request(0x0002);
  config_sm(line.segment, kStation, 1, kMbxInStart, kMbxLength, kMbxInControl, 0);  // SM1 disabled
  poll_slaves();
  EXPECT_EQ(al_status(), status(0x0011, 0x0016));
}

TEST_F(EsmOverEscTest, DeviceIdentificationShowsTheAlias) {
  EXPECT_EQ(request(0x0021), status(0x0021, 0x0ABC));  // alias from SII word 4
  EXPECT_EQ(request(0x0001), status(0x0001, 0));
}

TEST_F(EsmOverEscTest, ProcessDataWatchdogDropsOpToSafeOp) {
  // Watchdog: 100 µs base (0x0400 reset value), 0x0420 = 10 -> 1 ms.
  transact(line.segment, Command::Fpwr, fp(kStation, reg::kWatchdogTimeProcessData), le16(10), now());
  mailbox();
  request(0x0002);
  process();
  request(0x0004);
  transact(line.segment, Command::Fpwr, fp(kStation, kOutStart), Data(4, 1), now());  // outputs: trigger
  EXPECT_EQ(request(0x0008), status(0x0008, 0));
  line.clock.advance(std::chrono::microseconds(500));
  transact(line.segment, Command::Fpwr, fp(kStation, kOutStart), Data(4, 2), now());
  line.segment.poll(now());
  poll_slaves();
  EXPECT_EQ(al_status(), status(0x0008, 0));
  line.clock.advance(std::chrono::milliseconds(2));  // no outputs any more
  line.segment.poll(now());
  poll_slaves();
  EXPECT_EQ(al_status(), status(0x0014, 0x001B));
}

// A device with one byte of outputs: SM2 of length 1 is not activated as a
// buffer, "only Watchdog Trigger is generated" (Section II 0x0802). The
// master's LWR through the FMMU restarts the watchdog; without it the slave
// stays in Op with no outputs (ecat-conform config.watchdog_expiry).
TEST_F(EsmOverEscTest, OneByteOutputsWatchdogDropsOpToSafeOp) {
  constexpr std::uint32_t kLogical = 0x00010000;
  constexpr std::uint8_t kFmmuWrite = 2;
  transact(line.segment, Command::Fpwr, fp(kStation, reg::kWatchdogTimeProcessData), le16(10), now());  // 1 ms
  mailbox();
  request(0x0002);
  config_sm(line.segment, kStation, 2, kOutStart, 1, kOutControl);
  config_sm(line.segment, kStation, 3, kInStart, 6, kInControl);
  config_fmmu(line.segment, kStation, 0, kLogical, 1, 0, 7, kOutStart, 0, kFmmuWrite);
  request(0x0004);
  const auto outputs = [&](std::uint8_t v) {
    EXPECT_EQ(transact(line.segment, Command::Lwr, kLogical, Data{v}, now()).wkc, 1);
  };
  const auto pd_status = [&] {
    return transact(line.segment, Command::Fprd, fp(kStation, reg::kWatchdogStatusProcessData), 2, now()).data;
  };
  outputs(0x01);
  EXPECT_EQ(request(0x0008), status(0x0008, 0));
  line.clock.advance(std::chrono::microseconds(500));
  outputs(0x02);  // restarts: expiry now due 1 ms after this write
  const Nanoseconds last = now();
  line.clock.set(last + std::chrono::microseconds(999));
  line.segment.poll(now());
  poll_slaves();
  EXPECT_EQ(pd_status(), (Data{0x01, 0x00}));
  EXPECT_EQ(al_status(), status(0x0008, 0));
  line.clock.set(last + std::chrono::milliseconds(1));  // no outputs any more
  line.segment.poll(now());
  poll_slaves();
  EXPECT_EQ(pd_status(), (Data{0x00, 0x00}));
  EXPECT_EQ(al_status(), status(0x0014, 0x001B));
  EXPECT_EQ(line[0].memory()[kOutStart], 0x02);  // the byte itself is plain RAM
}

}  // namespace
}  // namespace ecat::esc::test
