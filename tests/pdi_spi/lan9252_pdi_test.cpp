// Lan9252Pdi: the exact SPI transactions for CSR register accesses, PRAM
// FIFO accesses, the options and bring-up (DS00001909; docs/real-esc.md).
#include "pdi_spi/lan9252_pdi.hpp"

#include <gtest/gtest.h>

#include "recording_bus.hpp"

namespace ecat::pdi_spi::test {
namespace {

// MISO of a 4-byte system register read: 3 header bytes, then the value.
Bytes reg_reply(std::uint32_t v, std::size_t header = 3) {
  Bytes b(header, 0);
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  return b;
}

TEST(Lan9252Pdi, CsrSizeIsNaturallyAligned) {
  EXPECT_EQ(lan9252_csr_size(0x0220, 4), 4u);
  EXPECT_EQ(lan9252_csr_size(0x0220, 3), 2u);
  EXPECT_EQ(lan9252_csr_size(0x0222, 4), 2u);
  EXPECT_EQ(lan9252_csr_size(0x0801, 4), 1u);
  EXPECT_EQ(lan9252_csr_size(0x0130, 1), 1u);
}

// AL event request 0x0220, 4 bytes: CSR command (busy | read | size 4 |
// address), one poll of ECAT_CSR_CMD, then ECAT_CSR_DATA.
TEST(Lan9252Pdi, RegisterReadIsCsrCommandPollData) {
  RecordingBus bus;
  bus.replies = {Bytes{}, reg_reply(0x00040220), reg_reply(0x00000911)};
  Lan9252Pdi pdi(bus);
  EXPECT_EQ(pdi.read_u32(0x0220), 0x00000911u);
  ASSERT_EQ(bus.sent.size(), 3u);
  EXPECT_EQ(bus.sent[0], (Bytes{0x02, 0x03, 0x04, 0x20, 0x02, 0x04, 0xC0}));
  EXPECT_EQ(bus.sent[1], (Bytes{0x03, 0x03, 0x04, 0, 0, 0, 0}));
  EXPECT_EQ(bus.sent[2], (Bytes{0x03, 0x03, 0x00, 0, 0, 0, 0}));
  EXPECT_EQ(pdi.counters().transactions, 3u);
  EXPECT_EQ(pdi.counters().bytes, 21u);
  EXPECT_FALSE(pdi.failed());
}

TEST(Lan9252Pdi, RegisterReadPollsUntilCsrBusyClears) {
  RecordingBus bus;
  bus.replies = {Bytes{}, reg_reply(0xC0020130), reg_reply(0xC0020130), reg_reply(0x40020130), reg_reply(0x0012)};
  Lan9252Pdi pdi(bus);
  EXPECT_EQ(pdi.read_u16(0x0130), 0x0012);
  ASSERT_EQ(bus.sent.size(), 5u);
  EXPECT_EQ(bus.sent[0], (Bytes{0x02, 0x03, 0x04, 0x30, 0x01, 0x02, 0xC0}));
}

// A write: ECAT_CSR_DATA, then the command (busy, R_nW = 0), then a poll.
TEST(Lan9252Pdi, RegisterWriteIsDataCommandPoll) {
  RecordingBus bus;
  Lan9252Pdi pdi(bus);
  pdi.write_u16(0x0134, 0x001B);
  ASSERT_EQ(bus.sent.size(), 3u);
  EXPECT_EQ(bus.sent[0], (Bytes{0x02, 0x03, 0x00, 0x1B, 0x00, 0x00, 0x00}));
  EXPECT_EQ(bus.sent[1], (Bytes{0x02, 0x03, 0x04, 0x34, 0x01, 0x02, 0x80}));
  EXPECT_EQ(bus.sent[2], (Bytes{0x03, 0x03, 0x04, 0, 0, 0, 0}));
}

// Five bytes at 0x0801: sizes 1, 2, 2 (never across natural alignment).
TEST(Lan9252Pdi, UnalignedRegisterReadSplitsByAlignment) {
  RecordingBus bus;
  Lan9252Pdi pdi(bus);
  std::uint8_t out[5];
  pdi.read(0x0801, out);
  ASSERT_EQ(bus.sent.size(), 9u);
  EXPECT_EQ(bus.sent[0], (Bytes{0x02, 0x03, 0x04, 0x01, 0x08, 0x01, 0xC0}));
  EXPECT_EQ(bus.sent[3], (Bytes{0x02, 0x03, 0x04, 0x02, 0x08, 0x02, 0xC0}));
  EXPECT_EQ(bus.sent[6], (Bytes{0x02, 0x03, 0x04, 0x04, 0x08, 0x02, 0xC0}));
}

// Process RAM 0x1002, 5 bytes: ADDR_LEN, CMD (busy), poll for
// PRAM_READ_AVAIL, then 8 FIFO bytes (2 lead, 5 data, 1 pad) in one burst.
TEST(Lan9252Pdi, ProcessRamReadIsOneFifoBurst) {
  RecordingBus bus;
  bus.replies = {Bytes{}, Bytes{}, reg_reply(0x80000201),
                 Bytes{0, 0, 0, 0xEE, 0xEE, 0x11, 0x22, 0x33, 0x44, 0x55, 0xEE}};
  Lan9252Pdi pdi(bus);
  std::uint8_t out[5]{};
  pdi.read(0x1002, out);
  ASSERT_EQ(bus.sent.size(), 4u);
  EXPECT_EQ(bus.sent[0], (Bytes{0x02, 0x03, 0x08, 0x02, 0x10, 0x05, 0x00}));
  EXPECT_EQ(bus.sent[1], (Bytes{0x02, 0x03, 0x0C, 0x00, 0x00, 0x00, 0x80}));
  EXPECT_EQ(bus.sent[2], (Bytes{0x03, 0x03, 0x0C, 0, 0, 0, 0}));
  EXPECT_EQ(bus.sent[3], (Bytes{0x03, 0x00, 0x00, 0, 0, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(Bytes(out, out + 5), (Bytes{0x11, 0x22, 0x33, 0x44, 0x55}));
}

TEST(Lan9252Pdi, ProcessRamWriteIsOneFifoBurst) {
  RecordingBus bus;
  bus.replies = {Bytes{}, Bytes{}, reg_reply(0x80001001)};
  Lan9252Pdi pdi(bus);
  const std::uint8_t in[3]{0xA1, 0xA2, 0xA3};
  pdi.write(0x1103, in);
  ASSERT_EQ(bus.sent.size(), 4u);
  EXPECT_EQ(bus.sent[0], (Bytes{0x02, 0x03, 0x10, 0x03, 0x11, 0x03, 0x00}));
  EXPECT_EQ(bus.sent[1], (Bytes{0x02, 0x03, 0x14, 0x00, 0x00, 0x00, 0x80}));
  EXPECT_EQ(bus.sent[2], (Bytes{0x03, 0x03, 0x14, 0, 0, 0, 0}));
  EXPECT_EQ(bus.sent[3], (Bytes{0x02, 0x00, 0x20, 0, 0, 0, 0xA1, 0xA2, 0xA3, 0, 0}));
}

TEST(Lan9252Pdi, FastReadAndBurstSetupAndNoCsrPoll) {
  RecordingBus bus;
  bus.replies = {Bytes{}, reg_reply(0x55667788, 4)};
  Lan9252Pdi pdi(bus, {.fast_read = true, .burst_setup = true, .skip_csr_poll = true});
  EXPECT_EQ(pdi.read_u32(0x0220), 0x55667788u);
  ASSERT_EQ(bus.sent.size(), 2u);
  EXPECT_EQ(bus.sent[1], (Bytes{0x0B, 0x03, 0x00, 0x00, 0, 0, 0, 0}));
  bus.sent.clear();
  bus.replies = {Bytes{}, reg_reply(0x80000101, 4), Bytes(8, 0x5A)};
  std::uint8_t out[4];
  pdi.read(0x1000, out);
  ASSERT_EQ(bus.sent.size(), 3u);
  EXPECT_EQ(bus.sent[0], (Bytes{0x02, 0x03, 0x08, 0x00, 0x10, 0x04, 0x00, 0x00, 0x00, 0x00, 0x80}));
  EXPECT_EQ(bus.sent[2], (Bytes{0x0B, 0x00, 0x00, 0x00, 0, 0, 0, 0}));
  EXPECT_EQ(Bytes(out, out + 4), Bytes(4, 0x5A));
}

// Bring-up: BYTE_TEST until the pattern, HW_CFG READY, then INT_EN = 0,
// IRQ_CFG = IRQ_EN | push-pull (active low), INT_EN = ECAT_INT.
TEST(Lan9252Pdi, InitChecksByteTestAndProgramsTheIrq) {
  RecordingBus bus;
  bus.replies = {reg_reply(0xFFFFFFFF), reg_reply(0x87654321), reg_reply(0x08000000)};
  Lan9252Pdi pdi(bus);
  ASSERT_TRUE(pdi.init()) << pdi.error();
  ASSERT_EQ(bus.sent.size(), 6u);
  EXPECT_EQ(bus.sent[0], (Bytes{0x03, 0x00, 0x64, 0, 0, 0, 0}));
  EXPECT_EQ(bus.sent[2], (Bytes{0x03, 0x00, 0x74, 0, 0, 0, 0}));
  EXPECT_EQ(bus.sent[3], (Bytes{0x02, 0x00, 0x5C, 0, 0, 0, 0}));
  EXPECT_EQ(bus.sent[4], (Bytes{0x02, 0x00, 0x54, 0x01, 0x01, 0, 0}));
  EXPECT_EQ(bus.sent[5], (Bytes{0x02, 0x00, 0x5C, 0x01, 0, 0, 0}));
}

TEST(Lan9252Pdi, ChipThatNeverAnswersFailsWithAMessage) {
  RecordingBus bus;
  Lan9252Pdi pdi(bus, {.max_polls = 5});
  EXPECT_FALSE(pdi.init());
  EXPECT_TRUE(pdi.failed());
  EXPECT_NE(std::string(pdi.error()).find("polled too long"), std::string::npos);
  EXPECT_EQ(bus.sent.size(), 5u);
}

TEST(Lan9252Pdi, BusErrorReadsZerosAndIsReported) {
  RecordingBus bus;
  bus.fail = true;
  bus.replies = {Bytes{}, reg_reply(0), reg_reply(0x12345678)};
  Lan9252Pdi pdi(bus);
  EXPECT_EQ(pdi.read_u32(0x0220), 0u);
  EXPECT_STREQ(pdi.error(), "SPI transfer failed");
  EXPECT_EQ(bus.sent.size(), 1u);  // nothing more after the failure
}

}  // namespace
}  // namespace ecat::pdi_spi::test
