// Register reset values, write masks and per-access side effects
// (Section II; esc-registers.md §3, §4, §11).
#include <gtest/gtest.h>

#include "esc/register_bits.hpp"
#include "esc_fixture.hpp"

namespace ecat::esc::test {
namespace {

constexpr std::uint16_t kStation = 0x1001;

struct RegTest : ::testing::Test {
  RegTest() : line(1) { assign_stations(line); }
  Line line;
  Esc& esc() { return line[0]; }
  Segment& seg() { return line.segment; }
  Reply rd(std::uint16_t ado, std::uint16_t len) { return transact(seg(), Command::Fprd, fp(kStation, ado), len); }
  Reply wr(std::uint16_t ado, const Data& d) { return transact(seg(), Command::Fpwr, fp(kStation, ado), d); }
};

TEST_F(RegTest, ResetValues) {
  auto r = rd(reg::kType, 10);
  // Type, revision, build, 8 FMMUs, 8 SMs, 8 KiB, ports 0/1 MII, features DC|DC64|enh. sync.
  EXPECT_EQ(r.data, (Data{0x11, 0x00, 0x00, 0x00, 8, 8, 8, 0x0F, 0x0C, 0x01}));
  EXPECT_EQ(esc().register_u16(reg::kDlControl), 0x0001);
  EXPECT_EQ(esc().register_u16(reg::kDlControl + 2), 0x0007);
  EXPECT_EQ(esc().register_u16(reg::kAlControl), 0x0001);
  EXPECT_EQ(esc().register_u16(reg::kAlStatus), 0x0001);
  EXPECT_EQ(esc().register_u16(reg::kAlStatusCode), 0x0000);
  EXPECT_EQ(esc().register_u16(reg::kWatchdogDivider), 0x09C2);
  EXPECT_EQ(esc().register_u16(reg::kWatchdogTimePdi), 0x03E8);
  EXPECT_EQ(esc().register_u16(reg::kWatchdogTimeProcessData), 0x03E8);
  EXPECT_EQ(esc().memory()[reg::kWatchdogStatusProcessData], 0x01);
  // From the SII configuration area (fixture: 0x0C05, 0x3344, 0x0064, 0x1234, alias 0x0ABC).
  r = rd(reg::kPdiControl, 2);
  EXPECT_EQ(r.data, (Data{0x05, 0x0C}));
  EXPECT_EQ(esc().register_u16(reg::kPdiConfiguration), 0x3344);
  EXPECT_EQ(esc().register_u16(reg::kExtendedPdiConfiguration), 0x1234);
  EXPECT_EQ(esc().register_u16(reg::kConfiguredStationAlias), 0x0ABC);
  EXPECT_EQ(esc().register_u16(0x0982), 0x0064);  // SYNC pulse length via the DC unit
  // SII control: 8-byte reads, not busy, checksum OK.
  EXPECT_EQ(esc().register_u16(reg::kEepromControlStatus), 0x0040);
}

TEST_F(RegTest, DlStatusOfOneSlave) {
  // PDI operational (EEPROM OK), port 0 link + communication, port 1 closed,
  // ports 2/3 (not implemented) closed.
  const std::uint16_t expect = 0x0001 | 0x0010 | 0x0200 | 0x0400 | 0x1000 | 0x4000;
  EXPECT_EQ(rd(reg::kDlStatus, 2).data, le16(expect));
}

TEST_F(RegTest, DlStatusInALineOfThree) {
  Line three(3);
  const std::uint16_t middle = 0x0001 | 0x0010 | 0x0020 | 0x0200 | 0x0800 | 0x1000 | 0x4000;
  const std::uint16_t last = 0x0001 | 0x0010 | 0x0200 | 0x0400 | 0x1000 | 0x4000;
  EXPECT_EQ(three[1].register_u16(reg::kDlStatus), middle);
  EXPECT_EQ(three[0].register_u16(reg::kDlStatus), middle);
  EXPECT_EQ(three[2].register_u16(reg::kDlStatus), last);
  // Forcing slave 1's port 1 closed (0x0101 = 0x0C): slave 2 is cut off.
  transact(three.segment, Command::Apwr, ap(1, reg::kDlControl + 1), Data{0x0C});
  EXPECT_EQ(three[1].register_u16(reg::kDlStatus) & 0x0400, 0x0400);
  EXPECT_EQ(transact(three.segment, Command::Brd, device_address(0, reg::kType), 1).wkc, 2);
  transact(three.segment, Command::Apwr, ap(1, reg::kDlControl + 1), Data{0x00});
  EXPECT_EQ(transact(three.segment, Command::Brd, device_address(0, reg::kType), 1).wkc, 3);
}

TEST_F(RegTest, SideMasks) {
  // ECAT cannot write AL status / status code / alias; the PDI can.
  wr(reg::kAlStatus, Data{0x08, 0x00});
  EXPECT_EQ(esc().register_u16(reg::kAlStatus), 0x0001);
  wr(reg::kConfiguredStationAlias, le16(0x7777));
  EXPECT_EQ(esc().register_u16(reg::kConfiguredStationAlias), 0x0ABC);
  esc().write_u16(reg::kAlStatus, 0x0012);
  esc().write_u16(reg::kAlStatusCode, 0x001B);
  EXPECT_EQ(rd(reg::kAlStatus, 6).data, (Data{0x12, 0x00, 0, 0, 0x1B, 0x00}));
  // PDI cannot write the station address or the ECAT event mask.
  esc().write_u16(reg::kConfiguredStationAddress, 0x4444);
  EXPECT_EQ(esc().register_u16(reg::kConfiguredStationAddress), kStation);
  // Only the defined AL control bits are kept.
  wr(reg::kAlControl, Data{0xF4, 0xFF});
  EXPECT_EQ(esc().register_u16(reg::kAlControl), 0x0034);
}

TEST_F(RegTest, AlControlEventAndMailboxBehaviour) {
  EXPECT_EQ(esc().irq(), false);
  esc().write_u32(reg::kAlEventMask, bits::kAlEventAlControl);
  EXPECT_EQ(wr(reg::kAlControl, le16(0x0002)).wkc, 1);
  EXPECT_EQ(esc().memory()[reg::kAlEventRequest] & 0x01, 0x01);
  EXPECT_TRUE(esc().irq());
  // Until the PDI reads 0x0120, a second ECAT write is not taken (Section II 0x0120).
  EXPECT_EQ(wr(reg::kAlControl, le16(0x0004)).wkc, 0);
  EXPECT_EQ(esc().read_u16(reg::kAlControl), 0x0002);
  EXPECT_EQ(esc().memory()[reg::kAlEventRequest] & 0x01, 0x00);
  EXPECT_FALSE(esc().irq());
  EXPECT_EQ(wr(reg::kAlControl, le16(0x0004)).wkc, 1);
  EXPECT_EQ(esc().read_u16(reg::kAlControl), 0x0004);
}

TEST_F(RegTest, AlStatusChangeRaisesEcatEventClearedByRead) {
  wr(reg::kEcatEventMask, le16(bits::kEcatEventAlStatus));
  rd(reg::kAlStatus, 2);
  esc().write_u16(reg::kAlStatus, 0x0002);
  TestFrame f;
  f.add(Command::Brd, device_address(0, reg::kType), 1);
  f.add(Command::Fprd, fp(kStation, reg::kAlStatus), 2);
  f.add(Command::Brd, device_address(0, reg::kType), 1);
  ASSERT_TRUE(f.send(seg()));
  EXPECT_EQ(f.dg(0).irq(), bits::kEcatEventAlStatus);
  EXPECT_EQ(f.data(1), le16(0x0002));
  EXPECT_EQ(f.dg(2).irq(), 0);  // acknowledged by the read in datagram 1
}

// The ESC keeps the ECAT event mask (Esc::irq_field asks for no event
// register while it is 0): every way of writing 0x0200 reaches the IRQ
// field of the next datagram - one byte, a raw poke, the reset.
TEST_F(RegTest, IrqFieldFollowsTheMaskAsLastWritten) {
  const auto irq = [&] {
    TestFrame f;
    f.add(Command::Brd, device_address(0, reg::kType), 1);
    EXPECT_TRUE(f.send(seg()));
    return f.dg(0).irq();
  };
  esc().write_u16(reg::kAlStatus, 0x0002);  // ECAT event bit 3 pending
  EXPECT_EQ(irq(), 0);
  wr(reg::kEcatEventMask, Data{bits::kEcatEventAlStatus});  // the low byte alone
  EXPECT_EQ(irq(), bits::kEcatEventAlStatus);
  esc().poke_registers(reg::kEcatEventMask, le16(0));
  EXPECT_EQ(irq(), 0);
  esc().poke_registers(reg::kEcatEventMask, le16(bits::kEcatEventAlStatus));
  EXPECT_EQ(irq(), bits::kEcatEventAlStatus);
  for (const std::uint8_t c : bits::kResetSequence) wr(reg::kEscResetEcat, Data{c});
  esc().write_u16(reg::kAlStatus, 0x0002);
  EXPECT_EQ(irq(), 0);
  EXPECT_EQ(esc().memory()[reg::kEcatEventRequest] & bits::kEcatEventAlStatus, bits::kEcatEventAlStatus);
}

TEST_F(RegTest, DeviceEmulationCopiesAlControl) {
  EscConfig cfg = make_config();
  cfg.sii.mutable_data()[1] = 0x01;  // 0x0141 bit 0
  cfg.sii.mutable_data()[14] = sii_crc(cfg.sii.bytes().first(kSiiConfigAreaBytes));
  Line l(1, cfg);
  transact(l.segment, Command::Apwr, ap(0, reg::kAlControl), le16(0x0008));
  EXPECT_EQ(l[0].register_u16(reg::kAlStatus), 0x0008);
  // Always writable in emulation mode.
  EXPECT_EQ(transact(l.segment, Command::Apwr, ap(0, reg::kAlControl), le16(0x0002)).wkc, 1);
  EXPECT_EQ(l[0].register_u16(reg::kAlStatus), 0x0002);
}

TEST_F(RegTest, RegisterWriteProtection) {
  wr(reg::kRegisterWriteProtection, Data{0x01});
  EXPECT_EQ(wr(reg::kEcatEventMask, le16(0x1234)).wkc, 0);
  EXPECT_EQ(esc().register_u16(reg::kEcatEventMask), 0);
  // Released by writing 0x0020 earlier in the same frame, for that frame only.
  TestFrame f;
  f.add(Command::Fpwr, fp(kStation, reg::kRegisterWriteEnable), Data{0x01});
  f.add(Command::Fpwr, fp(kStation, reg::kEcatEventMask), le16(0x1234));
  ASSERT_TRUE(f.send(seg()));
  EXPECT_EQ(f.wkc(1), 1);
  EXPECT_EQ(esc().register_u16(reg::kEcatEventMask), 0x1234);
  EXPECT_EQ(wr(reg::kEcatEventMask, le16(0)).wkc, 0);
  // RAM is not covered by register protection.
  EXPECT_EQ(wr(0x1000, Data{1}).wkc, 1);
}

// The DC registers lie inside 0x0000-0x0F7F, so register write protection
// covers them too (Section I §13; esc-registers.md §2): a write of the
// system time offset 0x0920 is discarded and not counted, whole (the DC
// block's own path) or as part of a wider write (the byte path).
TEST_F(RegTest, RegisterWriteProtectionCoversDcRegisters) {
  wr(reg::kRegisterWriteProtection, Data{0x01});
  EXPECT_EQ(wr(0x0920, Data{0x11, 0x22, 0x33, 0x44}).wkc, 0);
  EXPECT_EQ(esc().register_u16(0x0920), 0);
  EXPECT_EQ(wr(0x08FE, Data{0x01, 0x02, 0x11, 0x22}).wkc, 0);
  EXPECT_EQ(esc().register_u16(0x0900), 0);
  TestFrame f;
  f.add(Command::Fpwr, fp(kStation, reg::kRegisterWriteEnable), Data{0x01});
  f.add(Command::Fpwr, fp(kStation, 0x0920), Data{0x11, 0x22, 0x33, 0x44});
  ASSERT_TRUE(f.send(seg()));
  EXPECT_EQ(f.wkc(1), 1);
  EXPECT_EQ(esc().register_u16(0x0920), 0x2211);
}

TEST_F(RegTest, EscWriteProtectionCoversRam) {
  wr(reg::kEscWriteProtection, Data{0x01});
  EXPECT_EQ(wr(0x1000, Data{1}).wkc, 0);
  EXPECT_EQ(esc().memory()[0x1000], 0);
  TestFrame f;
  f.add(Command::Fpwr, fp(kStation, reg::kEscWriteEnable), Data{0x01});
  f.add(Command::Fpwr, fp(kStation, 0x1000), Data{1});
  ASSERT_TRUE(f.send(seg()));
  EXPECT_EQ(f.wkc(1), 1);
  EXPECT_EQ(esc().memory()[0x1000], 1);
}

TEST_F(RegTest, EscResetSequence) {
  wr(0x1000, Data{0x99});
  wr(reg::kEcatEventMask, le16(0x00FF));
  wr(reg::kEscResetEcat, Data{0x52});
  wr(reg::kEscResetEcat, Data{0x00});  // breaks the sequence
  wr(reg::kEscResetEcat, Data{0x45});
  wr(reg::kEscResetEcat, Data{0x53});
  EXPECT_EQ(esc().memory()[0x1000], 0x99);
  wr(reg::kEscResetEcat, Data{0x52});
  wr(reg::kEscResetEcat, Data{0x45});
  EXPECT_EQ(esc().memory()[0x1000], 0x99);
  wr(reg::kEscResetEcat, Data{0x53});
  EXPECT_EQ(esc().memory()[0x1000], 0x00);
  EXPECT_EQ(esc().register_u16(reg::kEcatEventMask), 0);
  EXPECT_EQ(esc().register_u16(reg::kConfiguredStationAddress), 0);
  EXPECT_EQ(esc().register_u16(reg::kConfiguredStationAlias), 0x0ABC);
  EXPECT_EQ(esc().register_u16(reg::kDlStatus) & 0x0010, 0x0010);  // links survive
  // The PDI has its own register 0x0041.
  esc().write_u8(0x1000, 1);
  esc().write_u8(reg::kEscResetPdi, 0x52);
  esc().write_u8(reg::kEscResetPdi, 0x45);
  esc().write_u8(reg::kEscResetPdi, 0x53);
  EXPECT_EQ(esc().memory()[0x1000], 0x00);
}

TEST_F(RegTest, WatchdogCountersClearTogether) {
  Data one{1};
  // Counters are read-only from the PDI side; set them through the test path.
  esc().count_rx_error(0, false);
  esc().count_rx_error(1, true);
  EXPECT_EQ(rd(reg::kRxErrorCounter, 12).data, (Data{1, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0}));
  // Writing any of 0x0300-0x030B clears them all.
  EXPECT_EQ(wr(reg::kRxErrorCounter + 5, one).wkc, 1);
  EXPECT_EQ(rd(reg::kRxErrorCounter, 12).data, Data(12, 0));
}

TEST_F(RegTest, MiiHasNoPhy) {
  EXPECT_EQ(wr(0x0510, le16(0x0100)).wkc, 1);  // read command
  EXPECT_EQ(rd(0x0510, 2).data, le16(0x2000));  // done at once, read error (no PHY)
  EXPECT_EQ(rd(0x0514, 2).data, le16(0));
  wr(0x0510, le16(0x0000));                     // idle clears the errors
  EXPECT_EQ(rd(0x0510, 2).data, le16(0));
  wr(0x0510, le16(0x0200));                     // write without write enable
  EXPECT_EQ(rd(0x0510, 2).data, le16(0x4000));
  wr(0x0510, le16(0x0201));                     // write with enable: accepted, nobody listens
  EXPECT_EQ(rd(0x0510, 2).data, le16(0x0001));
  wr(0x0510, le16(0x0300));                     // invalid command
  EXPECT_EQ(rd(0x0510, 2).data, le16(0x4000));
}

TEST_F(RegTest, BadSiiChecksum) {
  EscConfig cfg = make_config();
  cfg.sii.mutable_data()[14] ^= 0xFF;
  Line l(1, cfg);
  const std::uint16_t c = l[0].register_u16(reg::kEepromControlStatus);
  EXPECT_EQ(c & sii_bits::kChecksumError, sii_bits::kChecksumError);
  EXPECT_EQ(l[0].register_u16(reg::kDlStatus) & bits::kDlPdiOperational, 0);
  EXPECT_EQ(l[0].register_u16(reg::kConfiguredStationAlias), 0);
  EXPECT_EQ(l[0].register_u16(reg::kPdiControl), 0);
}

}  // namespace
}  // namespace ecat::esc::test

namespace ecat::esc::test {
namespace {

// Regression (fuzz_frame crash-fee71d73): writes to the reserved blocks
// 0x0700-0x07FF and 0x0880-0x08FF indexed past the FMMU/SM tables.
TEST(RegisterRegression, ReservedFmmuAndSmBlocksAreInert) {
  Line line(1);
  auto r = transact(line.segment, Command::Bwr, device_address(0, 0x0600), Data(0x0300, 0xFF));
  EXPECT_EQ(r.wkc, 1);
  for (std::uint16_t a = 0x0700; a < 0x0900; a = static_cast<std::uint16_t>(a + 0x10)) {
    if (a >= 0x0800 && a < 0x0880) continue;
    EXPECT_EQ(line[0].memory()[a], 0) << std::hex << a;
  }
  Data back(0x0300);
  line[0].read(0x0600, back);  // PDI reads of the same range have no side effects beyond the SMs
  EXPECT_EQ(back[0x0290], 0);
}

}  // namespace
}  // namespace ecat::esc::test
