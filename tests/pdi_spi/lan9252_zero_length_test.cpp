// A PRAM command of length 0 on the emulated LAN9252 (docs/pdi-host.md,
// "SOES's Linux LAN9252 HAL and a mailbox of length 0"): the FIFO gets no
// DWORD, so ECAT_PRAM_RD/WR_CMD never shows PRAM_*_AVAIL and the ESC is not
// accessed; a FIFO access after it is a violation. These are the exact
// transactions SOES's soes/hal/linux-lan9252/esc_hw.c clocks for
// ESC_read(0x1006, buf, 0) - it then polls ECAT_PRAM_RD_CMD for AVAIL
// forever - next to the same read of 2 bytes, which shows AVAIL at once.
#include <gtest/gtest.h>

#include <algorithm>

#include "esc/esc.hpp"
#include "pdi_spi/emulated_lan9252.hpp"
#include "recording_bus.hpp"
#include "tests/esc/esc_fixture.hpp"

namespace ecat::pdi_spi::test {
namespace {

Bytes clock_through(SpiBus& chip, const Bytes& tx) {
  Bytes rx(tx.size(), 0xEE);
  EXPECT_TRUE(chip.transfer(tx, rx));
  return rx;
}

struct Silicon {
  ManualClock clock;
  esc::Esc esc{esc::test::make_config(), clock};
};

// SERIAL READ of ECAT_PRAM_RD_CMD (0x30C) / ECAT_PRAM_WR_CMD (0x314).
const Bytes kReadRdCmd{0x03, 0x03, 0x0C, 0, 0, 0, 0};
const Bytes kReadWrCmd{0x03, 0x03, 0x14, 0, 0, 0, 0};

// SOES's sequence up to its AVAIL poll: abort, poll busy, ADDR_LEN, start.
void start_pram_read(SpiBus& chip, std::uint8_t length) {
  EXPECT_EQ(clock_through(chip, {0x02, 0x03, 0x0C, 0x00, 0x00, 0x00, 0x40}), Bytes(7, 0));  // PRAM_READ_ABORT
  EXPECT_EQ(clock_through(chip, kReadRdCmd), Bytes(7, 0));                                   // not busy
  clock_through(chip, {0x02, 0x03, 0x08, 0x06, 0x10, length, 0x00});  // address 0x1006, length
  clock_through(chip, {0x02, 0x03, 0x0C, 0x00, 0x00, 0x00, 0x80});    // PRAM_READ_BUSY: start
}

TEST(EmulatedLan9252ZeroLength, ReadOfZeroBytesNeverShowsAvailable) {
  Silicon s;
  const std::uint8_t pattern[] = {0xA1, 0xB2};
  s.esc.write(0x1006, pattern);
  EmulatedLan9252 chip(s.esc);
  start_pram_read(chip, 0);
  // ECAT_PRAM_RD_CMD = 0: not busy, PRAM_READ_AVAIL_CNT 0, PRAM_READ_AVAIL 0
  // - however often it is polled.
  for (int poll = 0; poll < 3; ++poll) EXPECT_EQ(clock_through(chip, kReadRdCmd), Bytes(7, 0));
  EXPECT_EQ(chip.violations(), 0u);
  // SOES then reads "the first value" from the FIFO: nothing is there.
  EXPECT_EQ(clock_through(chip, {0x03, 0x00, 0x00, 0, 0, 0, 0}), Bytes(7, 0));
  EXPECT_EQ(chip.violations(), 4u);
}

TEST(EmulatedLan9252ZeroLength, ReadOfTwoBytesShowsOneDwordAvailable) {
  Silicon s;
  const std::uint8_t pattern[] = {0xA1, 0xB2};
  s.esc.write(0x1006, pattern);
  EmulatedLan9252 chip(s.esc);
  start_pram_read(chip, 2);
  // 0x80000101: PRAM_READ_BUSY, PRAM_READ_AVAIL_CNT 1, PRAM_READ_AVAIL.
  EXPECT_EQ(clock_through(chip, kReadRdCmd), (Bytes{0, 0, 0, 0x01, 0x01, 0x00, 0x80}));
  // The DWORD carries 0x1006 in byte lane 2 (address & 3).
  EXPECT_EQ(clock_through(chip, {0x03, 0x00, 0x00, 0, 0, 0, 0}), (Bytes{0, 0, 0, 0, 0, 0xA1, 0xB2}));
  EXPECT_EQ(clock_through(chip, kReadRdCmd), Bytes(7, 0));  // done
  EXPECT_EQ(chip.violations(), 0u);
}

TEST(EmulatedLan9252ZeroLength, WriteOfZeroBytesNeverShowsAvailableNorWrites) {
  Silicon s;
  EmulatedLan9252 chip(s.esc);
  clock_through(chip, {0x02, 0x03, 0x10, 0x10, 0x10, 0x00, 0x00});  // ECAT_PRAM_WR_ADDR_LEN: 0x1010, 0 bytes
  clock_through(chip, {0x02, 0x03, 0x14, 0x00, 0x00, 0x00, 0x80});  // PRAM_WRITE_BUSY: start
  EXPECT_EQ(clock_through(chip, kReadWrCmd), Bytes(7, 0));
  // SOES's ESC_write_pram writes its first DWORD to the FIFO all the same.
  clock_through(chip, {0x02, 0x00, 0x20, 0x11, 0x22, 0x33, 0x44});
  EXPECT_EQ(chip.violations(), 4u);
  std::uint8_t ram[4]{};
  s.esc.read(0x1010, ram);
  EXPECT_TRUE(std::all_of(std::begin(ram), std::end(ram), [](std::uint8_t b) { return b == 0; }));
}

}  // namespace
}  // namespace ecat::pdi_spi::test
