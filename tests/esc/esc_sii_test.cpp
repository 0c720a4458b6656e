// The SII EEPROM interface as SOEM and IgH drive it (esc-registers.md §9,
// masters.md §6 #8/#9): address + command, poll busy, fetch the data.
#include <gtest/gtest.h>

#include "esc_fixture.hpp"

namespace ecat::esc::test {
namespace {

constexpr std::uint16_t kStation = 0x1001;

TEST(SiiCrc, WorkedExample) {
  // An all-zero configuration area gives 0x30 (sii-eeprom.md §2).
  std::array<std::uint8_t, 14> zero{};
  EXPECT_EQ(sii_crc(zero), 0x30);
  // Running the CRC over data + CRC yields 0.
  Data s = make_sii();
  EXPECT_EQ(sii_crc(std::span(s.data(), 15)), 0x00);
}

struct SiiTest : ::testing::Test {
  explicit SiiTest(Nanoseconds busy = 10us, bool eight = true) : line(1, cfg(busy, eight)) { assign_stations(line); }
  static EscConfig cfg(Nanoseconds busy, bool eight) {
    EscConfig c = make_config();
    c.sii_busy_time = busy;
    c.sii_read_8_bytes = eight;
    return c;
  }
  Segment& seg() { return line.segment; }
  Reply rd(std::uint16_t ado, std::uint16_t len, Nanoseconds t) {
    return transact(seg(), Command::Fprd, fp(kStation, ado), len, t);
  }
  Reply wr(std::uint16_t ado, const Data& d, Nanoseconds t) {
    return transact(seg(), Command::Fpwr, fp(kStation, ado), d, t);
  }
  Line line;
};

TEST_F(SiiTest, SoemStyleRead) {
  // SOEM: FPWR 0x0502 {command 0x0100, address, 0x0000}, poll, read 0x0508.
  auto st = rd(reg::kEepromControlStatus, 2, 0us);
  EXPECT_EQ(st.data, le16(0x0040));  // idle, 8-byte reads
  Data cmd{0x00, 0x01, 0x10, 0x00, 0x00, 0x00};
  EXPECT_EQ(wr(reg::kEepromControlStatus, cmd, 0us).wkc, 1);
  st = rd(reg::kEepromControlStatus, 2, 5us);
  EXPECT_EQ(st.data, le16(0x8140));  // busy, read command pending
  st = rd(reg::kEepromControlStatus, 2, 10us);
  EXPECT_EQ(st.data, le16(0x0040));
  auto d = rd(reg::kEepromData, 8, 10us);
  // Words 0x10..0x13 of the fixture image are 0x0110..0x0113.
  EXPECT_EQ(d.data, (Data{0x10, 0x01, 0x11, 0x01, 0x12, 0x01, 0x13, 0x01}));
}

TEST_F(SiiTest, IgHStyleReadWithAddressByteFlag) {
  // IgH: FPWR 0x0502 {0x80, 0x01, word address (2 bytes)}, then FPRD 10 bytes from 0x0502.
  wr(reg::kEepromControlStatus, Data{0x80, 0x01, 0x04, 0x00}, 0us);
  auto r = rd(reg::kEepromControlStatus, 10, 10us);
  EXPECT_EQ(r.data, (Data{0x40, 0x00, 0x04, 0x00, 0x00, 0x00, 0xBC, 0x0A, 0x00, 0x00}));
}

TEST_F(SiiTest, WritesWhileBusyAreIgnored) {
  wr(reg::kEepromControlStatus, Data{0x00, 0x01, 0x10, 0x00}, 0us);
  wr(reg::kEepromAddress, le16(0x20), 1us);  // ignored: busy
  rd(reg::kEepromControlStatus, 2, 10us);
  EXPECT_EQ(line[0].register_u16(reg::kEepromAddress), 0x10);
}

TEST_F(SiiTest, SoemStyleWordWriteAndWriteBack) {
  std::vector<std::pair<std::uint16_t, std::uint16_t>> written;
  EscConfig c = make_config();
  c.sii_write_back = [&](std::uint16_t a, std::uint16_t v) { written.emplace_back(a, v); };
  Line l(1, c);
  assign_stations(l);
  // Data first, then {0x0201 = enable + write, address}.
  transact(l.segment, Command::Fpwr, fp(kStation, reg::kEepromData), le16(0xBEEF));
  auto r = transact(l.segment, Command::Fpwr, fp(kStation, reg::kEepromControlStatus), Data{0x01, 0x02, 0x20, 0, 0, 0});
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(l[0].register_u16(reg::kEepromControlStatus), 0x0040);  // done, enable self-cleared
  ASSERT_EQ(written.size(), 1u);
  EXPECT_EQ(written[0], (std::pair<std::uint16_t, std::uint16_t>{0x20, 0xBEEF}));
  EXPECT_EQ(l[0].config().sii[0x40], 0xEF);
  EXPECT_EQ(l[0].config().sii[0x41], 0xBE);
  // Read it back (read size 8: the word and the next three).
  transact(l.segment, Command::Fpwr, fp(kStation, reg::kEepromControlStatus), Data{0x00, 0x01, 0x20, 0x00});
  EXPECT_EQ(transact(l.segment, Command::Fprd, fp(kStation, reg::kEepromData), 2).data, le16(0xBEEF));
}

TEST(SiiSharedImage, WriteCopiesTheImageForThatEscOnly) {
  // Two ESCs made from one config share its SII image (esc::EepromImage,
  // issue 16 item 5); a word written through ESC 0's EEPROM interface
  // changes ESC 0's image only, and survives ESC 0's reload.
  Line l(2);
  assign_stations(l);
  EXPECT_EQ(l[0].config().sii.data(), l[1].config().sii.data());
  EXPECT_TRUE(l[0].config().sii.shared());
  const std::uint8_t before_lo = l[1].config().sii[0x40];
  const std::uint8_t before_hi = l[1].config().sii[0x41];
  transact(l.segment, Command::Fpwr, fp(kStation, reg::kEepromData), le16(0xBEEF));
  EXPECT_EQ(transact(l.segment, Command::Fpwr, fp(kStation, reg::kEepromControlStatus), Data{0x01, 0x02, 0x20, 0, 0, 0}).wkc, 1);
  EXPECT_NE(l[0].config().sii.data(), l[1].config().sii.data());
  EXPECT_EQ(l[0].config().sii[0x40], 0xEF);
  EXPECT_EQ(l[0].config().sii[0x41], 0xBE);
  EXPECT_EQ(l[1].config().sii[0x40], before_lo);
  EXPECT_EQ(l[1].config().sii[0x41], before_hi);
  EXPECT_EQ(l[0].config().sii.size(), l[1].config().sii.size());
  // ESC 1 reads the old word, ESC 0 the new one, also after a reload command (0x0400).
  const Data read_word_0x20{0x00, 0x01, 0x20, 0x00};
  transact(l.segment, Command::Fpwr, fp(kStation + 1, reg::kEepromControlStatus), read_word_0x20);
  EXPECT_EQ(transact(l.segment, Command::Fprd, fp(kStation + 1, reg::kEepromData), 2).data,
            (Data{before_lo, before_hi}));
  transact(l.segment, Command::Fpwr, fp(kStation, reg::kEepromControlStatus), Data{0x00, 0x04});
  transact(l.segment, Command::Fpwr, fp(kStation, reg::kEepromControlStatus), read_word_0x20);
  EXPECT_EQ(transact(l.segment, Command::Fprd, fp(kStation, reg::kEepromData), 2).data, le16(0xBEEF));
  // A second write goes into ESC 0's own copy in place.
  const std::uint8_t* own = l[0].config().sii.data();
  transact(l.segment, Command::Fpwr, fp(kStation, reg::kEepromData), le16(0x1234));
  transact(l.segment, Command::Fpwr, fp(kStation, reg::kEepromControlStatus), Data{0x01, 0x02, 0x20, 0, 0, 0});
  EXPECT_EQ(l[0].config().sii.data(), own);
  EXPECT_EQ(l[0].config().sii[0x40], 0x34);
  EXPECT_EQ(l[1].config().sii[0x40], before_lo);
}

TEST_F(SiiTest, ErrorsAndClear) {
  // Write without enable -> bit 14; idle command clears the error bits.
  wr(reg::kEepromControlStatus, Data{0x00, 0x02, 0x20, 0x00}, 0us);
  EXPECT_EQ(rd(reg::kEepromControlStatus, 2, 10us).data, le16(0x4040));
  wr(reg::kEepromControlStatus, Data{0x00, 0x00}, 10us);
  EXPECT_EQ(rd(reg::kEepromControlStatus, 2, 10us).data, le16(0x0040));
  // An invalid command (0b011) -> acknowledge/command error bit 13.
  wr(reg::kEepromControlStatus, Data{0x00, 0x03}, 20us);
  EXPECT_EQ(rd(reg::kEepromControlStatus, 2, 30us).data, le16(0x2040));
  // Reading past the image returns erased words.
  wr(reg::kEepromControlStatus, Data{0x00, 0x01, 0x00, 0x10, 0x00, 0x00}, 40us);
  EXPECT_EQ(rd(reg::kEepromData, 4, 50us).data, (Data{0xFF, 0xFF, 0xFF, 0xFF}));
}

TEST_F(SiiTest, PdiOwnership) {
  // 0x0500 bit 0 offers the EEPROM to the PDI, which takes it in 0x0501.
  wr(reg::kEepromConfiguration, Data{0x01}, 0us);
  line[0].write_u8(reg::kEepromPdiAccessState, 0x01);
  // Now ECAT commands are ignored...
  wr(reg::kEepromControlStatus, Data{0x00, 0x01, 0x10, 0x00}, 0us);
  EXPECT_EQ(rd(reg::kEepromControlStatus, 2, 20us).data, le16(0x0040));
  EXPECT_EQ(line[0].register_u16(reg::kEepromAddress), 0);
  // ...and a 2-byte ECAT write of 0x0002 forces the PDI off (masters.md §6 #9).
  wr(reg::kEepromConfiguration, le16(0x0002), 20us);
  EXPECT_EQ(line[0].memory()[reg::kEepromPdiAccessState], 0);
  EXPECT_EQ(line[0].memory()[reg::kEepromConfiguration], 0);
  wr(reg::kEepromControlStatus, Data{0x00, 0x01, 0x10, 0x00}, 20us);
  EXPECT_EQ(line[0].register_u16(reg::kEepromAddress), 0x10);
}

struct SiiFourByteTest : SiiTest {
  SiiFourByteTest() : SiiTest(0us, false) {}
};

TEST_F(SiiFourByteTest, ReadsFourBytesAtOnce) {
  EXPECT_EQ(rd(reg::kEepromControlStatus, 2, 0us).data, le16(0x0000));
  wr(reg::kEepromControlStatus, Data{0x00, 0x01, 0x08, 0x00}, 0us);
  // No busy time configured: finished in the same frame.
  EXPECT_EQ(rd(reg::kEepromData, 8, 0us).data, (Data{0x08, 0x01, 0x09, 0x01, 0, 0, 0, 0}));
}

TEST_F(SiiTest, ReloadKeepsAliasAndReportsChecksum) {
  line[0].write_u16(reg::kConfiguredStationAlias, 0x5555);  // PDI changes the alias
  // Corrupt word 0 through the write command, then reload: checksum error.
  wr(reg::kEepromData, le16(0x0C06), 0us);
  wr(reg::kEepromControlStatus, Data{0x01, 0x02, 0x00, 0x00}, 0us);
  rd(reg::kEepromControlStatus, 2, 10us);
  wr(reg::kEepromControlStatus, Data{0x00, 0x04}, 10us);
  EXPECT_EQ(rd(reg::kEepromControlStatus, 2, 20us).data, le16(0x1840));
  EXPECT_EQ(line[0].register_u16(reg::kConfiguredStationAlias), 0x5555);
  EXPECT_EQ(line[0].register_u16(reg::kDlStatus) & 0x0001, 0);  // EEPROM not loaded correctly
  // Repair word 0 and reload again: loaded, and 0x0140 follows the image.
  wr(reg::kEepromData, le16(0x0C05), 20us);
  wr(reg::kEepromControlStatus, Data{0x01, 0x02, 0x00, 0x00}, 20us);
  wr(reg::kEepromControlStatus, Data{0x00, 0x04}, 30us);
  line[0].poll(40us);
  EXPECT_EQ(line[0].register_u16(reg::kEepromControlStatus), 0x0040);
  EXPECT_EQ(line[0].register_u16(reg::kDlStatus) & 0x0001, 1);
}

}  // namespace
}  // namespace ecat::esc::test
