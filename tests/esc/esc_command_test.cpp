// Every command with its WKC on one slave and on a line of three
// (ETG.1000.4 §5.4; Section I Tables 5 and 7).
#include <gtest/gtest.h>

#include "esc_fixture.hpp"

namespace ecat::esc::test {
namespace {

constexpr std::uint16_t kRam = 0x1000;

TEST(Commands, AutoIncrementOnOneSlave) {
  Line line(1);
  auto r = transact(line.segment, Command::Aprd, ap(0, reg::kType), 2);
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(r.data, (Data{kEscTypeEt1100, 0x00}));
  EXPECT_EQ(r.adp, 1);  // incremented by the slave
  r = transact(line.segment, Command::Apwr, ap(0, kRam), Data{0xAA, 0xBB});
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(line[0].memory()[kRam], 0xAA);
  r = transact(line.segment, Command::Aprw, ap(0, kRam), Data{0x11, 0x22});
  EXPECT_EQ(r.wkc, 3);
  EXPECT_EQ(r.data, (Data{0xAA, 0xBB}));  // old value returned
  EXPECT_EQ(line[0].memory()[kRam + 1], 0x22);
  // Position 1 does not exist: nothing answers.
  r = transact(line.segment, Command::Aprd, ap(1, kRam), 2);
  EXPECT_EQ(r.wkc, 0);
  EXPECT_EQ(r.data, (Data{0, 0}));
  EXPECT_EQ(r.adp, 0x0000);  // 0xFFFF + 1
}

TEST(Commands, AutoIncrementOnThree) {
  Line line(3);
  auto r = transact(line.segment, Command::Apwr, ap(1, kRam), Data{0x5A});
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(r.adp, 2);  // 0xFFFF + 3
  EXPECT_EQ(line[0].memory()[kRam], 0x00);
  EXPECT_EQ(line[1].memory()[kRam], 0x5A);
  EXPECT_EQ(line[2].memory()[kRam], 0x00);
  r = transact(line.segment, Command::Aprd, ap(2, kRam), 1);
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(r.data, Data{0x00});
  r = transact(line.segment, Command::Aprw, ap(1, kRam), Data{0x77});
  EXPECT_EQ(r.wkc, 3);
  EXPECT_EQ(r.data, Data{0x5A});
}

TEST(Commands, ConfiguredAddressOnThree) {
  Line line(3);
  assign_stations(line);
  EXPECT_EQ(line[2].register_u16(reg::kConfiguredStationAddress), 0x1003);
  auto r = transact(line.segment, Command::Fpwr, fp(0x1002, kRam), Data{1, 2, 3});
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(r.adp, 0x1002);  // FP leaves ADP alone
  EXPECT_EQ(line[1].memory()[kRam + 2], 3);
  EXPECT_EQ(line[0].memory()[kRam + 2], 0);
  r = transact(line.segment, Command::Fprd, fp(0x1002, kRam), 3);
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(r.data, (Data{1, 2, 3}));
  r = transact(line.segment, Command::Fprw, fp(0x1002, kRam), Data{9, 9, 9});
  EXPECT_EQ(r.wkc, 3);
  EXPECT_EQ(r.data, (Data{1, 2, 3}));
  r = transact(line.segment, Command::Fprd, fp(0x2000, kRam), 3);
  EXPECT_EQ(r.wkc, 0);
}

TEST(Commands, AliasAddressingNeedsDlControlBit24) {
  Line line(2);
  assign_stations(line);
  // Alias 0x0ABC comes from SII word 4 on both; only slave 1 enables it.
  EXPECT_EQ(line[1].register_u16(reg::kConfiguredStationAlias), 0x0ABC);
  auto r = transact(line.segment, Command::Fprd, fp(0x0ABC, reg::kType), 1);
  EXPECT_EQ(r.wkc, 0);
  transact(line.segment, Command::Fpwr, fp(0x1002, reg::kDlControl + 3), Data{0x01});
  r = transact(line.segment, Command::Fpwr, fp(0x0ABC, kRam), Data{0x42});
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(line[1].memory()[kRam], 0x42);
  EXPECT_EQ(line[0].memory()[kRam], 0x00);
  // The station address still works too.
  EXPECT_EQ(transact(line.segment, Command::Fprd, fp(0x1002, kRam), 1).wkc, 1);
}

TEST(Commands, BroadcastOnThree) {
  Line line(3);
  assign_stations(line);
  transact(line.segment, Command::Fpwr, fp(0x1001, kRam), Data{0x01});
  transact(line.segment, Command::Fpwr, fp(0x1003, kRam), Data{0x80});
  auto r = transact(line.segment, Command::Brd, device_address(0, kRam), 1);
  EXPECT_EQ(r.wkc, 3);
  EXPECT_EQ(r.data, Data{0x81});  // ORed
  EXPECT_EQ(r.adp, 3);            // one increment per slave
  r = transact(line.segment, Command::Bwr, device_address(0, kRam + 4), Data{0xEE});
  EXPECT_EQ(r.wkc, 3);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(line[i].memory()[kRam + 4], 0xEE);
  r = transact(line.segment, Command::Brw, device_address(0, kRam), Data{0x10});
  EXPECT_EQ(r.wkc, 9);
  EXPECT_EQ(r.data, Data{0x91});  // incoming OR every slave's old value
  // Each slave writes the data as it arrives, i.e. already ORed upstream.
  EXPECT_EQ(line[0].memory()[kRam], 0x10);
  EXPECT_EQ(line[1].memory()[kRam], 0x11);
  EXPECT_EQ(line[2].memory()[kRam], 0x11);
}

TEST(Commands, ReadMultipleWriteOnThree) {
  Line line(3);
  assign_stations(line);
  transact(line.segment, Command::Fpwr, fp(0x1001, kRam), Data{0xCA, 0xFE});
  // FRMW at slave 1: it reads, the others write what it read.
  auto r = transact(line.segment, Command::Frmw, fp(0x1001, kRam), 2);
  EXPECT_EQ(r.wkc, 3);
  EXPECT_EQ(r.data, (Data{0xCA, 0xFE}));
  EXPECT_EQ(line[1].memory()[kRam], 0xCA);
  EXPECT_EQ(line[2].memory()[kRam + 1], 0xFE);
  // ARMW addressed at position 1: slave 0 writes (zeros), slave 1 reads, slave 2 writes.
  transact(line.segment, Command::Fpwr, fp(0x1002, kRam + 8), Data{0x33});
  r = transact(line.segment, Command::Armw, ap(1, kRam + 8), 1);
  EXPECT_EQ(r.wkc, 3);
  EXPECT_EQ(r.data, Data{0x33});
  EXPECT_EQ(line[0].memory()[kRam + 8], 0x00);
  EXPECT_EQ(line[2].memory()[kRam + 8], 0x33);
  EXPECT_EQ(r.adp, 2);
}

TEST(Commands, NopTouchesNothing) {
  Line line(2);
  auto r = transact(line.segment, Command::Nop, device_address(0, kRam), Data{1, 2});
  EXPECT_EQ(r.wkc, 0);
  EXPECT_EQ(r.adp, 0);
  EXPECT_EQ(line[0].memory()[kRam], 0);
}

TEST(Commands, UnsupportedCommandsPassUntouched) {
  EscConfig cfg = make_config();
  cfg.lrw = false;
  cfg.read_write_commands = false;
  Line line(2, cfg);
  EXPECT_EQ(line[0].register_u16(reg::kFeatures) & 0x0600, 0x0600);
  auto r = transact(line.segment, Command::Brw, device_address(0, kRam), Data{0x10});
  EXPECT_EQ(r.wkc, 0);
  EXPECT_EQ(r.adp, 2);
  EXPECT_EQ(line[0].memory()[kRam], 0);
  r = transact(line.segment, Command::Aprw, ap(0, kRam), Data{0x10});
  EXPECT_EQ(r.wkc, 0);
  config_fmmu(line.segment, 0, 0, 0x10000, 1, 0, 7, kRam, 0, 3);  // station 0 = both (unset)
  r = transact(line.segment, Command::Lrw, 0x10000, Data{0x55});
  EXPECT_EQ(r.wkc, 0);
  EXPECT_EQ(r.data, Data{0x55});
  EXPECT_EQ(transact(line.segment, Command::Lwr, 0x10000, Data{0x55}).wkc, 2);  // both slaves
}

TEST(Commands, ReservedRegistersCountButKeepValue) {
  Line line(1);
  // Writing read-only bytes of an implemented block still counts (masters.md §6 #5).
  auto r = transact(line.segment, Command::Bwr, device_address(0, reg::kType), Data{0xFF, 0xFF});
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(line[0].memory()[reg::kType], kEscTypeEt1100);
  // Memory past the process RAM (8 KiB -> ends at 0x3000) is not there.
  EXPECT_EQ(transact(line.segment, Command::Brd, device_address(0, 0x3000), 4).wkc, 0);
  EXPECT_EQ(transact(line.segment, Command::Brd, device_address(0, 0x2FFE), 4).wkc, 1);
}

// The AL status poll (BRD of 0x0130, 2 bytes) has its own case in the
// engine: every ESC ORs both bytes in, counts 1, adds 1 to the ADP and
// acknowledges its ECAT event bit 3 (Section II 0x0130/0x0210), so the
// IRQ field it ORs in after the read has no bit 3. A BRD of 1 byte of
// 0x0130, or of 0x0130-0x0131 from 0x012F, takes the general path alike.
TEST(Commands, BrdOfAlStatusOrsEveryEscAndAcknowledgesItsEvent) {
  Line line(3);
  assign_stations(line);
  const std::uint16_t status[] = {0x0002, 0x0004, 0x0012};  // PreOp, SafeOp, SafeOp + error
  for (std::size_t i = 0; i < 3; ++i) {
    transact(line.segment, Command::Fpwr, fp(static_cast<std::uint16_t>(0x1001 + i), reg::kEcatEventMask),
             le16(bits::kEcatEventAlStatus));
    line[i].write_u16(reg::kAlStatus, status[i]);  // raises ECAT event bit 3
  }
  TestFrame f;
  f.add(Command::Brd, device_address(0x0100, reg::kAlStatus), Data{0x20, 0x00});
  f.add(Command::Brd, device_address(0, reg::kAlStatus), 1);
  f.add(Command::Brd, device_address(0, reg::kAlStatus - 1), 3);
  ASSERT_TRUE(f.send(line.segment));
  EXPECT_EQ(f.data(0), (Data{0x36, 0x00}));  // the incoming bits stay
  EXPECT_EQ(f.wkc(0), 3);
  EXPECT_EQ(f.dg(0).adp(), 0x0103);
  EXPECT_EQ(f.dg(0).irq(), 0);
  EXPECT_EQ(f.data(1), Data{0x16});
  EXPECT_EQ(f.wkc(1), 3);
  EXPECT_EQ(f.data(2), (Data{0x00, 0x16, 0x00}));
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(line[i].memory()[reg::kEcatEventRequest] & bits::kEcatEventAlStatus, 0) << i;
  }
  // Raised again: the poll acknowledges it again.
  line[1].write_u16(reg::kAlStatus, 0x0008);
  EXPECT_EQ(line[1].memory()[reg::kEcatEventRequest] & bits::kEcatEventAlStatus, bits::kEcatEventAlStatus);
  TestFrame g;
  g.add(Command::Brd, device_address(0, reg::kAlStatus), 2);
  ASSERT_TRUE(g.send(line.segment));
  EXPECT_EQ(g.data(0), (Data{0x1A, 0x00}));
  EXPECT_EQ(line[1].memory()[reg::kEcatEventRequest] & bits::kEcatEventAlStatus, 0);
}

TEST(Commands, SeveralDatagramsInOneFrame) {
  Line line(3);
  assign_stations(line);
  TestFrame f;
  f.add(Command::Fpwr, fp(0x1003, kRam), Data{0xAB});
  f.add(Command::Fprd, fp(0x1003, kRam), 1);
  f.add(Command::Brd, device_address(0, reg::kAlStatus), 2);
  ASSERT_TRUE(f.send(line.segment));
  EXPECT_EQ(f.wkc(0), 1);
  EXPECT_EQ(f.wkc(1), 1);
  EXPECT_EQ(f.data(1), Data{0xAB});
  EXPECT_EQ(f.wkc(2), 3);
  EXPECT_EQ(f.data(2), (Data{0x01, 0x00}));
}

}  // namespace
}  // namespace ecat::esc::test

namespace ecat::esc::test {
namespace {

// masters.md §6 #6: the DC block answers (and counts) only when 0x0008 bit 2 says DC is there.
TEST(Commands, DcBlockCountsOnlyWithDc) {
  Line with(3);
  EXPECT_EQ(with[0].register_u16(reg::kFeatures) & 0x000C, 0x000C);
  EXPECT_EQ(transact(with.segment, Command::Bwr, device_address(0, reg::kDcBase), Data(4, 0)).wkc, 3);
  EscConfig cfg = make_config();
  cfg.dc = false;
  Line without(3, cfg);
  EXPECT_EQ(without[0].register_u16(reg::kFeatures) & 0x010C, 0);
  EXPECT_EQ(transact(without.segment, Command::Bwr, device_address(0, reg::kDcBase), Data(4, 0)).wkc, 0);
  auto r = transact(without.segment, Command::Brd, device_address(0, 0x0910), Data(8, 0x5A));
  EXPECT_EQ(r.wkc, 0);
  EXPECT_EQ(r.data, Data(8, 0x5A));
  // The ECAT read/write paths of the other commands (wholly inside the block
  // or across its start), with and without DC.
  r = transact(without.segment, Command::Aprd, ap(0, 0x0910), Data(8, 0x5A));
  EXPECT_EQ(r.wkc, 0);
  EXPECT_EQ(r.data, Data(8, 0x5A));
  EXPECT_EQ(transact(without.segment, Command::Armw, ap(0, 0x0910), Data(8, 0x5A)).wkc, 0);
  EXPECT_EQ(transact(without.segment, Command::Apwr, ap(1, 0x0920), Data(8, 0)).wkc, 0);
  EXPECT_EQ(transact(without.segment, Command::Aprd, ap(0, 0x08FC), Data(8, 0)).wkc, 1);  // SM bytes count
  EXPECT_EQ(transact(with.segment, Command::Armw, ap(0, 0x0910), Data(8, 0)).wkc, 3);
  EXPECT_EQ(transact(with.segment, Command::Apwr, ap(1, 0x0920), Data(8, 0)).wkc, 1);
  EXPECT_EQ(transact(with.segment, Command::Aprd, ap(2, 0x08FC), Data(8, 0)).wkc, 1);
}

}  // namespace
}  // namespace ecat::esc::test
