// Logical addressing through FMMUs: bit-granular mappings, overlaps,
// direction, several FMMUs in one datagram (Section I §6; ETG.1000.4 §5.4.3).
#include <gtest/gtest.h>

#include "esc_fixture.hpp"

namespace ecat::esc::test {
namespace {

constexpr std::uint8_t kRead = 1;
constexpr std::uint8_t kWrite = 2;
constexpr std::uint16_t kStation = 0x1001;

struct FmmuTest : ::testing::Test {
  FmmuTest() : line(1) { assign_stations(line); }
  Line line;
  Segment& seg() { return line.segment; }
  const std::uint8_t* mem() { return line[0].memory(); }
};

// The datasheet example (Section I §6): 14 bits from logical 0x00010011.3 to
// 0x00010013.0 onto physical 0x0F01.1-0x0F02.6, length 3.
TEST_F(FmmuTest, DatasheetBitMapping) {
  config_fmmu(seg(), kStation, 0, 0x00010011, 3, 3, 0, 0x0F01, 1, kRead | kWrite);
  auto r = transact(seg(), Command::Lwr, 0x00010010, Data{0xFF, 0xF8, 0xFF, 0x01});
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(mem()[0x0F00], 0x00);
  EXPECT_EQ(mem()[0x0F01], 0xFE);
  EXPECT_EQ(mem()[0x0F02], 0x7F);
  EXPECT_EQ(mem()[0x0F03], 0x00);
  // Only the mapped bits change in memory: set bit 7 of 0x0F02 and write zeros.
  transact(seg(), Command::Fpwr, fp(kStation, 0x0F02), Data{0xFF});
  r = transact(seg(), Command::Lwr, 0x00010011, Data{0x00, 0x00, 0x00});
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(mem()[0x0F01], 0x00);
  EXPECT_EQ(mem()[0x0F02], 0x80);
  // Read: mapped bits replaced, unmapped bits keep the incoming data.
  transact(seg(), Command::Fpwr, fp(kStation, 0x0F01), Data{0x02, 0x40});  // first and last mapped bit
  r = transact(seg(), Command::Lrd, 0x00010010, Data{0xAA, 0xAA, 0xAA, 0xAA});
  EXPECT_EQ(r.wkc, 1);
  // byte 1 bits 3..7 <- phys bits 1..5 of 0x0F01 (only bit 1 set) -> 0b00001 at bit 3
  // byte 2 <- phys 0x0F01 bits 6,7 and 0x0F02 bits 0..5 -> 0
  // byte 3 bit 0 <- 0x0F02 bit 6 = 1
  EXPECT_EQ(r.data, (Data{0xAA, 0x0A, 0x00, 0xAB}));
}

TEST_F(FmmuTest, LrwBitMappedWriteBehindAReadByte) {
  // Read FMMU on logical byte 0x10010, bit-wise write FMMU from 0x10011.3:
  // the write must use the data as it arrived, offset within the datagram.
  config_fmmu(seg(), kStation, 0, 0x00010011, 3, 3, 0, 0x0F01, 1, kWrite);
  config_fmmu(seg(), kStation, 1, 0x00010010, 1, 0, 7, 0x1000, 0, kRead);
  transact(seg(), Command::Fpwr, fp(kStation, 0x1000), Data{0x3C});
  auto r = transact(seg(), Command::Lrw, 0x00010010, Data{0x00, 0xF8, 0xFF, 0x01});
  EXPECT_EQ(r.wkc, 3);
  EXPECT_EQ(r.data, (Data{0x3C, 0xF8, 0xFF, 0x01}));
  EXPECT_EQ(mem()[0x0F01], 0xFE);
  EXPECT_EQ(mem()[0x0F02], 0x7F);
}

TEST_F(FmmuTest, ByteAlignedLogicalOntoOddPhysicalBit) {
  // 8 bits from logical 0x20000.0 onto physical 0x1000.4 .. 0x1001.3.
  config_fmmu(seg(), kStation, 0, 0x20000, 1, 0, 7, 0x1000, 4, kWrite);
  EXPECT_EQ(transact(seg(), Command::Lwr, 0x20000, Data{0xA5}).wkc, 1);
  EXPECT_EQ(mem()[0x1000], 0x50);
  EXPECT_EQ(mem()[0x1001], 0x0A);
}

TEST_F(FmmuTest, PartialOverlapWithDatagram) {
  config_fmmu(seg(), kStation, 0, 0x30004, 4, 0, 7, 0x1010, 0, kRead);
  transact(seg(), Command::Fpwr, fp(kStation, 0x1010), Data{1, 2, 3, 4});
  // Datagram covers logical 0x30002..0x30005: the last two bytes hit the FMMU.
  auto r = transact(seg(), Command::Lrd, 0x30002, Data{9, 9, 9, 9});
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(r.data, (Data{9, 9, 1, 2}));
  // Datagram ends before the FMMU starts: no hit.
  r = transact(seg(), Command::Lrd, 0x30000, Data{9, 9, 9, 9});
  EXPECT_EQ(r.wkc, 0);
  EXPECT_EQ(r.data, (Data{9, 9, 9, 9}));
}

TEST_F(FmmuTest, DirectionIsRespected) {
  config_fmmu(seg(), kStation, 0, 0x40000, 2, 0, 7, 0x1020, 0, kRead);
  config_fmmu(seg(), kStation, 1, 0x50000, 2, 0, 7, 0x1030, 0, kWrite);
  // LWR on a read-only mapping: nothing written, not counted.
  EXPECT_EQ(transact(seg(), Command::Lwr, 0x40000, Data{7, 7}).wkc, 0);
  EXPECT_EQ(mem()[0x1020], 0);
  // LRD on a write-only mapping: data untouched, not counted.
  transact(seg(), Command::Fpwr, fp(kStation, 0x1030), Data{5, 5});
  auto r = transact(seg(), Command::Lrd, 0x50000, Data{1, 1});
  EXPECT_EQ(r.wkc, 0);
  EXPECT_EQ(r.data, (Data{1, 1}));
  // Disabled FMMU: no hit at all.
  transact(seg(), Command::Fpwr, fp(kStation, reg::fmmu(0) + 0xC), Data{0});
  EXPECT_EQ(transact(seg(), Command::Lrd, 0x40000, 2).wkc, 0);
}

TEST_F(FmmuTest, TwoFmmusInOneLrwCountThree) {
  // Outputs logical 0x60000..1 -> 0x1100, inputs logical 0x60002..3 <- 0x1200.
  config_fmmu(seg(), kStation, 0, 0x60000, 2, 0, 7, 0x1100, 0, kWrite);
  config_fmmu(seg(), kStation, 1, 0x60002, 2, 0, 7, 0x1200, 0, kRead);
  transact(seg(), Command::Fpwr, fp(kStation, 0x1200), Data{0xC1, 0xC2});
  auto r = transact(seg(), Command::Lrw, 0x60000, Data{0x0A, 0x0B, 0xEE, 0xEE});
  EXPECT_EQ(r.wkc, 3);
  EXPECT_EQ(r.data, (Data{0x0A, 0x0B, 0xC1, 0xC2}));
  EXPECT_EQ(mem()[0x1100], 0x0A);
  EXPECT_EQ(mem()[0x1101], 0x0B);
  // LRD over the same image counts only the read; LWR only the write.
  EXPECT_EQ(transact(seg(), Command::Lrd, 0x60000, 4).wkc, 1);
  EXPECT_EQ(transact(seg(), Command::Lwr, 0x60000, 4).wkc, 1);
}

TEST_F(FmmuTest, OverlappingReadAndWriteOfSameBytesReturnsOldValue) {
  // Both FMMUs on the same logical and physical bytes.
  config_fmmu(seg(), kStation, 0, 0x70000, 1, 0, 7, 0x1300, 0, kWrite);
  config_fmmu(seg(), kStation, 1, 0x70000, 1, 0, 7, 0x1300, 0, kRead);
  transact(seg(), Command::Fpwr, fp(kStation, 0x1300), Data{0x11});
  auto r = transact(seg(), Command::Lrw, 0x70000, Data{0x22});
  EXPECT_EQ(r.wkc, 3);
  EXPECT_EQ(r.data, Data{0x11});
  EXPECT_EQ(mem()[0x1300], 0x22);
}

TEST_F(FmmuTest, MailboxStateBitIntoLogicalImage) {
  // SOEM/TwinCAT map SM1 status bit 3 (mailbox full) into the image.
  config_sm(seg(), kStation, 1, 0x1800, 32, 0x22);
  config_fmmu(seg(), kStation, 2, 0x80000, 1, 0, 0, reg::sync_manager(1) + reg::sm::kStatus, 3, kRead);
  EXPECT_EQ(transact(seg(), Command::Lrd, 0x80000, 1).data, Data{0x00});
  Data reply(32, 0x5A);
  line[0].write(0x1800, reply);  // the PDI fills the read mailbox
  auto r = transact(seg(), Command::Lrd, 0x80000, Data{0xF0});
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(r.data, Data{0xF1});
}

// An ESC skips a logical datagram outside the span of all its active FMMUs
// (issue 8 quick reject): the edges of the span, the gap between two FMMUs,
// the top of the 4 GiB space, bit-granular FMMUs and no active FMMU at all.
TEST_F(FmmuTest, LogicalSpanEdges) {
  config_fmmu(seg(), kStation, 0, 0x100, 4, 0, 7, 0x1000, 0, kWrite);
  config_fmmu(seg(), kStation, 1, 0x200, 4, 0, 7, 0x1100, 0, kRead);
  transact(seg(), Command::Fpwr, fp(kStation, 0x1100), Data{0x11, 0x22, 0x33, 0x44});
  EXPECT_EQ(transact(seg(), Command::Lwr, 0x0FC, Data{1, 2, 3, 4}).wkc, 0);  // ends just before the span
  EXPECT_EQ(mem()[0x1000], 0x00);
  EXPECT_EQ(transact(seg(), Command::Lwr, 0x0FD, Data{1, 2, 3, 4}).wkc, 1);  // last byte is the first mapped
  EXPECT_EQ(mem()[0x1000], 0x04);
  EXPECT_EQ(transact(seg(), Command::Lrd, 0x150, 16).wkc, 0);  // the gap between the FMMUs
  EXPECT_EQ(transact(seg(), Command::Lrd, 0x204, 2).wkc, 0);   // starts just past the span
  auto r = transact(seg(), Command::Lrd, 0x203, 2);             // first byte is the last mapped
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(r.data, (Data{0x44, 0x00}));
  // Top of the logical space: the span end lies past 2^32.
  config_fmmu(seg(), kStation, 2, 0xFFFFFFFE, 2, 0, 7, 0x1200, 0, kWrite);
  EXPECT_EQ(transact(seg(), Command::Lwr, 0xFFFFFFFF, Data{0x5A}).wkc, 1);
  EXPECT_EQ(mem()[0x1201], 0x5A);
  // A bit-granular FMMU (general path): bits 4..3 of the next byte, logical 0x300-0x301.
  config_fmmu(seg(), kStation, 3, 0x300, 2, 4, 3, 0x1300, 0, kWrite);
  EXPECT_EQ(transact(seg(), Command::Lwr, 0x2FF, Data{0xFF}).wkc, 0);
  EXPECT_EQ(transact(seg(), Command::Lwr, 0x302, Data{0xFF}).wkc, 0);
  EXPECT_EQ(transact(seg(), Command::Lwr, 0x301, Data{0xFF}).wkc, 1);
  // No active FMMU: nothing is mapped anywhere.
  for (unsigned n = 0; n < 4; ++n) transact(seg(), Command::Fpwr, fp(kStation, reg::fmmu(n) + 0xC), Data{0});
  EXPECT_EQ(transact(seg(), Command::Lrw, 0x0, Data(1024, 0)).wkc, 0);
  EXPECT_EQ(transact(seg(), Command::Lrw, 0x100, 4).wkc, 0);
  EXPECT_EQ(mem()[0x1000], 0x04);
}

TEST(FmmuLine, ThreeSlavesLrwCountsNine) {
  Line line(3);
  assign_stations(line);
  for (std::uint16_t i = 0; i < 3; ++i) {
    const auto st = static_cast<std::uint16_t>(0x1001 + i);
    config_fmmu(line.segment, st, 0, 0x100 + 2u * i, 2, 0, 7, 0x1000, 0, kWrite);
    config_fmmu(line.segment, st, 1, 0x200 + 2u * i, 2, 0, 7, 0x1400, 0, kRead);
    transact(line.segment, Command::Fpwr, fp(st, 0x1400), Data{static_cast<std::uint8_t>(0xA0 + i), 0xBB});
  }
  TestFrame f;
  f.add(Command::Lrw, 0x100, Data{1, 2, 3, 4, 5, 6});
  f.add(Command::Lrw, 0x200, 6);
  ASSERT_TRUE(f.send(line.segment));
  EXPECT_EQ(f.wkc(0), 6);  // writes only: 2 per slave
  EXPECT_EQ(f.wkc(1), 3);  // reads only: 1 per slave
  EXPECT_EQ(f.data(1), (Data{0xA0, 0xBB, 0xA1, 0xBB, 0xA2, 0xBB}));
  EXPECT_EQ(line[2].memory()[0x1000], 5);
  EXPECT_EQ(line[2].memory()[0x1001], 6);
  // One LRW covering the whole image: each slave reads and writes -> 3 x 3.
  auto r = transact(line.segment, Command::Lrw, 0x100, 0x106);
  EXPECT_EQ(r.wkc, 9);
}

}  // namespace
}  // namespace ecat::esc::test
