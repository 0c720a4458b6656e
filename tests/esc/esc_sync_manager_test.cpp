// SyncManager buffer rules from both sides (Section I §8; esc-registers.md §7).
#include <gtest/gtest.h>

#include "esc/register_bits.hpp"
#include "esc_fixture.hpp"

namespace ecat::esc::test {
namespace {

constexpr std::uint16_t kStation = 0x1001;
constexpr std::uint16_t kMbxOut = 0x1000;  // SM0: master -> slave
constexpr std::uint16_t kMbxIn = 0x1080;   // SM1: slave -> master
constexpr std::uint16_t kMbxLen = 8;
constexpr std::uint16_t kOutputs = 0x1100;  // SM2, 3-buffer, ECAT writes
constexpr std::uint16_t kInputs = 0x1200;   // SM3, 3-buffer, ECAT reads
constexpr std::uint16_t kPdLen = 4;

std::uint8_t sm_status(Esc& esc, unsigned n) { return esc.memory()[reg::sync_manager(n) + reg::sm::kStatus]; }

struct SmTest : ::testing::Test {
  SmTest() : line(1) {
    assign_stations(line);
    config_sm(seg(), kStation, 0, kMbxOut, kMbxLen, 0x26);
    config_sm(seg(), kStation, 1, kMbxIn, kMbxLen, 0x22);
    config_sm(seg(), kStation, 2, kOutputs, kPdLen, 0x64);
    config_sm(seg(), kStation, 3, kInputs, kPdLen, 0x20);
  }
  Line line;
  Esc& esc() { return line[0]; }
  Segment& seg() { return line.segment; }
  std::uint32_t al_event() { return esc().read_u32(reg::kAlEventRequest); }
};

TEST_F(SmTest, WriteMailboxFullOnLastByteAndFreedByPdiRead) {
  EXPECT_EQ(sm_status(esc(), 0), 0x00);
  Data req{1, 2, 3, 4, 5, 6, 7, 8};
  EXPECT_EQ(transact(seg(), Command::Fpwr, fp(kStation, kMbxOut), req).wkc, 1);
  EXPECT_EQ(sm_status(esc(), 0) & sm_bits::kStatusMailboxFull, sm_bits::kStatusMailboxFull);
  EXPECT_EQ(al_event() & (1u << 8), 1u << 8);  // SM0 AL event (control bit 5)
  // Full: a second write is refused and not counted; memory unchanged.
  EXPECT_EQ(transact(seg(), Command::Fpwr, fp(kStation, kMbxOut), Data(8, 0xEE)).wkc, 0);
  EXPECT_EQ(esc().memory()[kMbxOut], 1);
  // The master cannot read its own write mailbox.
  EXPECT_EQ(transact(seg(), Command::Fprd, fp(kStation, kMbxOut), 8).wkc, 0);
  // The PDI reads it: reading the first byte clears the AL event, the last byte empties.
  Data got(8);
  esc().read(kMbxOut, std::span(got).first(4));
  EXPECT_EQ(al_event() & (1u << 8), 0u);
  EXPECT_NE(sm_status(esc(), 0) & sm_bits::kStatusMailboxFull, 0);
  esc().read(kMbxOut + 4, std::span(got).subspan(4));
  EXPECT_EQ(got, req);
  EXPECT_EQ(sm_status(esc(), 0) & sm_bits::kStatusMailboxFull, 0);
  EXPECT_EQ(transact(seg(), Command::Fpwr, fp(kStation, kMbxOut), Data(8, 0xEE)).wkc, 1);
}

TEST_F(SmTest, WriteMailboxUsedPartThenLastByte) {
  // TwinCAT writes the used part, then the last byte (masters.md §6 #15).
  EXPECT_EQ(transact(seg(), Command::Fpwr, fp(kStation, kMbxOut), Data{1, 2, 3}).wkc, 1);
  EXPECT_EQ(sm_status(esc(), 0) & sm_bits::kStatusMailboxFull, 0);
  EXPECT_EQ(transact(seg(), Command::Fpwr, fp(kStation, kMbxOut + 7), Data{9}).wkc, 1);
  EXPECT_NE(sm_status(esc(), 0) & sm_bits::kStatusMailboxFull, 0);
}

TEST_F(SmTest, ReadMailboxEmptyGivesWkcZero) {
  auto r = transact(seg(), Command::Fprd, fp(kStation, kMbxIn), Data(8, 0x77));
  EXPECT_EQ(r.wkc, 0);
  EXPECT_EQ(r.data, Data(8, 0x77));  // not overwritten
  Data reply{0xA, 0xB, 0xC, 0xD, 0xE, 0xF, 0x1, 0x2};
  esc().write(kMbxIn, reply);
  EXPECT_NE(sm_status(esc(), 1) & sm_bits::kStatusMailboxFull, 0);
  // The PDI cannot overwrite a full read mailbox.
  esc().write(kMbxIn, Data(8, 0));
  EXPECT_EQ(esc().memory()[kMbxIn], 0xA);
  // The master reads it in two datagrams; the second (with the last byte) frees it.
  TestFrame f;
  f.add(Command::Fprd, fp(kStation, kMbxIn), 5);
  f.add(Command::Fprd, fp(kStation, kMbxIn + 5), 3);
  ASSERT_TRUE(f.send(seg()));
  EXPECT_EQ(f.wkc(0), 1);
  EXPECT_EQ(f.wkc(1), 1);
  EXPECT_EQ(f.data(0), (Data{0xA, 0xB, 0xC, 0xD, 0xE}));
  EXPECT_EQ(f.data(1), (Data{0xF, 0x1, 0x2}));
  EXPECT_EQ(sm_status(esc(), 1) & sm_bits::kStatusMailboxFull, 0);
  EXPECT_EQ(al_event() & (1u << 9), 1u << 9);  // SM1 read by ECAT -> PDI told
  EXPECT_EQ(transact(seg(), Command::Fprd, fp(kStation, kMbxIn), 8).wkc, 0);
}

TEST_F(SmTest, RepeatRequestAndAcknowledge) {
  // Master toggles 0x080E bit 1; the ESC raises AL event bit 4; the PDI acks in 0x080F.
  esc().read_u32(reg::kAlEventRequest);
  (void)esc().read_u8(reg::sync_manager(1) + reg::sm::kActivate);  // clears bit 4
  EXPECT_EQ(al_event() & bits::kAlEventSmActivation, 0u);
  EXPECT_EQ(transact(seg(), Command::Fpwr, fp(kStation, reg::sync_manager(1) + reg::sm::kActivate), Data{0x03}).wkc,
            1);
  EXPECT_NE(al_event() & bits::kAlEventSmActivation, 0u);
  const std::uint8_t act = esc().read_u8(reg::sync_manager(1) + reg::sm::kActivate);
  EXPECT_EQ(act, 0x03);
  EXPECT_EQ(al_event() & bits::kAlEventSmActivation, 0u);
  esc().write_u8(reg::sync_manager(1) + reg::sm::kPdiControl, sm_bits::kPdiRepeatAck);
  auto r = transact(seg(), Command::Fprd, fp(kStation, reg::sync_manager(1) + reg::sm::kPdiControl), 1);
  EXPECT_EQ(r.data, Data{0x02});
  // The master cannot write the PDI control byte.
  transact(seg(), Command::Fpwr, fp(kStation, reg::sync_manager(1) + reg::sm::kPdiControl), Data{0x00});
  EXPECT_EQ(esc().memory()[reg::sync_manager(1) + reg::sm::kPdiControl], 0x02);
}

TEST_F(SmTest, PdiDeactivationBlocksTheBuffer) {
  esc().write_u8(reg::sync_manager(0) + reg::sm::kPdiControl, sm_bits::kPdiDeactivate);
  EXPECT_EQ(transact(seg(), Command::Fpwr, fp(kStation, kMbxOut), Data(8, 1)).wkc, 0);
  esc().write_u8(reg::sync_manager(0) + reg::sm::kPdiControl, 0);
  EXPECT_EQ(transact(seg(), Command::Fpwr, fp(kStation, kMbxOut), Data(8, 1)).wkc, 1);
}

TEST_F(SmTest, ConfigurationLockedWhileEnabled) {
  transact(seg(), Command::Fpwr, fp(kStation, reg::sync_manager(0)), le16(0x1400));
  EXPECT_EQ(esc().register_u16(reg::sync_manager(0)), kMbxOut);
  // Disable, then the start address can change.
  transact(seg(), Command::Fpwr, fp(kStation, reg::sync_manager(0) + reg::sm::kActivate), Data{0});
  transact(seg(), Command::Fpwr, fp(kStation, reg::sync_manager(0)), le16(0x1400));
  EXPECT_EQ(esc().register_u16(reg::sync_manager(0)), 0x1400);
  // Disabled SM: its old area is plain memory again.
  EXPECT_EQ(transact(seg(), Command::Fprd, fp(kStation, kMbxOut), 8).wkc, 1);
}

TEST_F(SmTest, ThreeBufferOutputsExchangeOnLastByte) {
  EXPECT_EQ(sm_status(esc(), 2) & sm_bits::kStatusBufferMask, 0x30);  // nothing written yet
  EXPECT_EQ(transact(seg(), Command::Fpwr, fp(kStation, kOutputs), Data{1, 1, 1, 1}).wkc, 1);
  EXPECT_EQ(transact(seg(), Command::Fpwr, fp(kStation, kOutputs), Data{2, 2, 2, 2}).wkc, 1);
  // Buffered mode is always writable; the PDI gets the latest complete buffer.
  Data got(4);
  esc().read(kOutputs, got);
  EXPECT_EQ(got, (Data{2, 2, 2, 2}));
  // A partial write (no last byte) does not exchange.
  transact(seg(), Command::Fpwr, fp(kStation, kOutputs), Data{3, 3});
  esc().read(kOutputs, got);
  EXPECT_EQ(got, (Data{2, 2, 2, 2}));
  // The rest, with the last byte, completes buffer {3,3,4,4}.
  transact(seg(), Command::Fpwr, fp(kStation, kOutputs + 2), Data{4, 4});
  esc().read(kOutputs, got);
  EXPECT_EQ(got, (Data{3, 3, 4, 4}));
  // Buffers 1/2 live behind buffer 0 in RAM (start + len, start + 2 len).
  const std::uint8_t* m = esc().memory();
  EXPECT_EQ((m[kOutputs] == 3) + (m[kOutputs + 4] == 3) + (m[kOutputs + 8] == 3), 1);
  EXPECT_EQ((m[kOutputs] == 2) + (m[kOutputs + 4] == 2) + (m[kOutputs + 8] == 2), 1);
}

TEST_F(SmTest, ThreeBufferReaderKeepsItsBufferAcrossTwoDatagrams) {
  esc().write(kInputs, Data{1, 1, 1, 1});
  // The master opens the buffer with the first half...
  auto r = transact(seg(), Command::Fprd, fp(kStation, kInputs), 2);
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(r.data, (Data{1, 1}));
  // ...the application writes two newer buffers meanwhile...
  esc().write(kInputs, Data{2, 2, 2, 2});
  esc().write(kInputs, Data{3, 3, 3, 3});
  // ...the second half still comes from the buffer the master opened.
  r = transact(seg(), Command::Fprd, fp(kStation, kInputs + 2), 2);
  EXPECT_EQ(r.data, (Data{1, 1}));
  // The next read gets the latest.
  r = transact(seg(), Command::Fprd, fp(kStation, kInputs), 4);
  EXPECT_EQ(r.data, (Data{3, 3, 3, 3}));
  EXPECT_NE(sm_status(esc(), 3) & sm_bits::kStatusReadEvent, 0);
}

TEST_F(SmTest, EcatEventWhenPdiCompletesBuffer) {
  // SM1 with ECAT event enable (control bit 4): PDI write -> 0x0210 bit 5, mask -> IRQ field.
  transact(seg(), Command::Fpwr, fp(kStation, reg::sync_manager(1) + reg::sm::kActivate), Data{0});
  config_sm(seg(), kStation, 1, kMbxIn, kMbxLen, 0x32);
  transact(seg(), Command::Fpwr, fp(kStation, reg::kEcatEventMask), le16(0x0020));
  esc().write(kMbxIn, Data(8, 1));
  auto r = transact(seg(), Command::Fprd, fp(kStation, reg::kEcatEventRequest), 2);
  EXPECT_EQ(r.data[0] & 0x20, 0x20);
  TestFrame f;
  f.add(Command::Nop, 0, 2);
  ASSERT_TRUE(f.send(seg()));
  EXPECT_EQ(f.dg(0).irq(), 0x0020);
  // Reading the SM status from ECAT acknowledges it.
  transact(seg(), Command::Fprd, fp(kStation, reg::sync_manager(1) + reg::sm::kStatus), 1);
  EXPECT_EQ(transact(seg(), Command::Fprd, fp(kStation, reg::kEcatEventRequest), 2).data[0] & 0x20, 0);
}

}  // namespace
}  // namespace ecat::esc::test
