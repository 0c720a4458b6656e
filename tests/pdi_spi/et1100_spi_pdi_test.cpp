// Et1100SpiPdi: the exact SPI transactions of the ET1100/ET1200 SPI PDI
// (ESC datasheet Section III; docs/real-esc.md): address phase, command,
// wait-state byte, read termination, 3-byte addressing, AL event bytes.
#include "pdi_spi/et1100_spi_pdi.hpp"

#include <gtest/gtest.h>

#include "recording_bus.hpp"

namespace ecat::pdi_spi::test {
namespace {

// AL status 0x0130, 2 bytes: A[12:5] = 0x09, A[4:0] = 0x10 -> 0x80 | read
// with wait state (3); wait-state byte 0xFF; 0x00 then 0xFF (termination).
TEST(Et1100SpiPdi, ReadWithWaitStateAndTermination) {
  RecordingBus bus;
  bus.replies = {Bytes{0x01, 0x00, 0xFF, 0x08, 0x00}};
  Et1100SpiPdi pdi(bus);
  EXPECT_EQ(pdi.read_u16(0x0130), 0x0008);
  ASSERT_EQ(bus.sent.size(), 1u);
  EXPECT_EQ(bus.sent[0], (Bytes{0x09, 0x83, 0xFF, 0x00, 0xFF}));
  EXPECT_EQ(pdi.last_al_event(), 0x0001);  // MISO of the address phase
}

TEST(Et1100SpiPdi, ReadWithoutWaitState) {
  RecordingBus bus;
  Et1100SpiPdi pdi(bus, {.wait_state = false});
  std::uint8_t out[4];
  pdi.read(0x1100, out);
  EXPECT_EQ(bus.sent[0], (Bytes{0x88, 0x02, 0x00, 0x00, 0x00, 0xFF}));
}

TEST(Et1100SpiPdi, WriteIsAddressPhaseThenData) {
  RecordingBus bus;
  bus.replies = {Bytes{0x00, 0x01}};
  Et1100SpiPdi pdi(bus);
  pdi.write_u16(0x0134, 0x001B);
  ASSERT_EQ(bus.sent.size(), 1u);
  EXPECT_EQ(bus.sent[0], (Bytes{0x09, 0xA4, 0x1B, 0x00}));
  EXPECT_EQ(pdi.last_al_event(), 0x0100);
}

// Above 0x1FFF: address-extension command 6 in byte 1, then A[15:13] << 5 |
// command << 2 in byte 2.
TEST(Et1100SpiPdi, ThreeByteAddressAboveThirteenBits) {
  RecordingBus bus;
  Et1100SpiPdi pdi(bus);
  std::uint8_t out[1];
  pdi.read(0x3000, out);
  EXPECT_EQ(bus.sent[0], (Bytes{0x80, 0x06, 0x2C, 0xFF, 0xFF}));
  pdi.write_u8(0x2FFF, 0x42);
  EXPECT_EQ(bus.sent[1], (Bytes{0x7F, 0xFE, 0x30, 0x42}));
  Et1100SpiPdi always(bus, {.three_byte_address = true});
  always.write_u8(0x0120, 0x02);
  EXPECT_EQ(bus.sent[2], (Bytes{0x09, 0x06, 0x10, 0x02}));
}

// A read of 0x0220..0x0223 takes 0x0220/0x0221 from the address phase and
// reads only 0x0222/0x0223: 5 bytes instead of 7.
TEST(Et1100SpiPdi, AlEventReadPiggybacksOnTheAddressPhase) {
  RecordingBus bus;
  bus.replies = {Bytes{0x11, 0x09, 0xFF, 0x00, 0x00}};
  Et1100SpiPdi pdi(bus);
  EXPECT_EQ(pdi.read_u32(0x0220), 0x00000911u);
  ASSERT_EQ(bus.sent.size(), 1u);
  EXPECT_EQ(bus.sent[0], (Bytes{0x11, 0x13, 0xFF, 0x00, 0xFF}));
  EXPECT_EQ(pdi.counters().bytes, 5u);
  // Two bytes: the address phase of a NOP is all it takes.
  bus.replies = {Bytes{0x01, 0x02}};
  EXPECT_EQ(pdi.read_u16(0x0220), 0x0201);
  EXPECT_EQ(bus.sent[1], (Bytes{0x11, 0x10}));
}

TEST(Et1100SpiPdi, LongAccessesSplitIntoBursts) {
  RecordingBus bus;
  Et1100SpiPdi pdi(bus);
  std::vector<std::uint8_t> big(Et1100SpiPdi::kMaxBurst + 10, 0x33);
  pdi.write(0x1000, big);
  ASSERT_EQ(bus.sent.size(), 2u);
  EXPECT_EQ(bus.sent[0].size(), 2 + Et1100SpiPdi::kMaxBurst);
  EXPECT_EQ(bus.sent[1].size(), 2u + 10u);
  const auto second = static_cast<std::uint16_t>(0x1000 + Et1100SpiPdi::kMaxBurst);
  EXPECT_EQ(bus.sent[1][0], static_cast<std::uint8_t>(second >> 5));
}

TEST(Et1100SpiPdi, BusErrorReadsZerosAndIsReported) {
  RecordingBus bus;
  bus.fail = true;
  bus.replies = {Bytes{0, 0, 0xFF, 0x12, 0x34}};
  Et1100SpiPdi pdi(bus);
  EXPECT_EQ(pdi.read_u16(0x0130), 0);
  EXPECT_TRUE(pdi.failed());
}

}  // namespace
}  // namespace ecat::pdi_spi::test
