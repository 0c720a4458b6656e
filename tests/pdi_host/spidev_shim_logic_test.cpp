// The spidev shim's logic without a process (pdi_client/spidev_frame.*,
// pdi_client/gpio_edges.*; docs/firmware-in-the-loop.md): how the transfers
// of an SPI_IOC_MESSAGE become chip-select windows (exact MOSI bytes per
// window, MISO bytes back into each transfer's rx_buf), checked against a
// recording window and against the emulated LAN9252; and which GPIO edges
// and events the ESC's IRQ / SYNC lines make.
#include <gtest/gtest.h>
#include <linux/gpio.h>

#include <cerrno>
#include <cstdint>
#include <vector>

#include "common/clock.hpp"
#include "esc/esc.hpp"
#include "gpio_edges.h"
#include "pdi_client/ecat_pdi_protocol.h"
#include "pdi_spi/emulated_lan9252.hpp"
#include "pdi_spi/lan9252_registers.hpp"
#include "spidev_frame.h"
#include "tests/esc/esc_fixture.hpp"

namespace ecat::pdi_host::test {
namespace {

using Bytes = std::vector<std::uint8_t>;

// Records each window's MOSI bytes and answers MISO = MOSI ^ 0xFF, or fails.
struct Recorder {
  std::vector<Bytes> windows;
  bool fail = false;
  static int window(void* ctx, std::uint8_t* buf, std::size_t len) {
    auto* self = static_cast<Recorder*>(ctx);
    if (self->fail) return -1;
    self->windows.emplace_back(buf, buf + len);
    for (std::size_t i = 0; i < len; ++i) buf[i] = static_cast<std::uint8_t>(buf[i] ^ 0xFFu);
    return 0;
  }
};

spi_ioc_transfer xfer(const Bytes* tx, Bytes* rx, std::uint32_t len, bool cs_change = false) {
  spi_ioc_transfer t{};
  t.tx_buf = tx != nullptr ? reinterpret_cast<std::uintptr_t>(tx->data()) : 0;
  t.rx_buf = rx != nullptr ? reinterpret_cast<std::uintptr_t>(rx->data()) : 0;
  t.len = len;
  t.cs_change = cs_change ? 1 : 0;
  return t;
}

long run(std::vector<spi_ioc_transfer>& xfers, Recorder& r, std::size_t scratch_size = 64) {
  std::vector<std::uint8_t> scratch(scratch_size);
  return spidev_run_message(xfers.data(), static_cast<unsigned>(xfers.size()), scratch.data(), scratch.size(),
                            &Recorder::window, &r);
}

TEST(SpidevFrame, TransfersWithoutCsChangeAreOneWindow) {
  Bytes a{0x03, 0x00, 0x64}, b{0xAA, 0xBB, 0xCC, 0xDD}, ra(3, 0xEE), rb(4, 0xEE);
  std::vector<spi_ioc_transfer> x{xfer(&a, &ra, 3), xfer(&b, &rb, 4)};
  Recorder r;
  EXPECT_EQ(run(x, r), 7);
  ASSERT_EQ(r.windows.size(), 1u);
  EXPECT_EQ(r.windows[0], (Bytes{0x03, 0x00, 0x64, 0xAA, 0xBB, 0xCC, 0xDD}));
  EXPECT_EQ(ra, (Bytes{0xFC, 0xFF, 0x9B}));
  EXPECT_EQ(rb, (Bytes{0x55, 0x44, 0x33, 0x22}));
}

TEST(SpidevFrame, CsChangeBeforeTheLastTransferOpensANewWindow) {
  Bytes a{1, 2}, b{3}, c{4, 5}, ra(2), rb(1), rc(2);
  std::vector<spi_ioc_transfer> x{xfer(&a, &ra, 2, true), xfer(&b, &rb, 1), xfer(&c, &rc, 2)};
  Recorder r;
  EXPECT_EQ(run(x, r), 5);
  ASSERT_EQ(r.windows.size(), 2u);
  EXPECT_EQ(r.windows[0], (Bytes{1, 2}));
  EXPECT_EQ(r.windows[1], (Bytes{3, 4, 5}));
  EXPECT_EQ(ra, (Bytes{0xFE, 0xFD}));
  EXPECT_EQ(rb, (Bytes{0xFC}));
  EXPECT_EQ(rc, (Bytes{0xFB, 0xFA}));
}

TEST(SpidevFrame, CsChangeOnTheLastTransferStillEndsTheMessage) {
  Bytes a{9, 8}, b{7};
  std::vector<spi_ioc_transfer> x{xfer(&a, nullptr, 2), xfer(&b, nullptr, 1, true)};
  Recorder r;
  EXPECT_EQ(run(x, r), 3);
  ASSERT_EQ(r.windows.size(), 1u);
  EXPECT_EQ(r.windows[0], (Bytes{9, 8, 7}));
}

TEST(SpidevFrame, NoTxBufferClocksZerosAndNoRxBufferDropsTheInput) {
  Bytes a{0x11, 0x22}, rb(3, 0xEE);
  std::vector<spi_ioc_transfer> x{xfer(&a, nullptr, 2), xfer(nullptr, &rb, 3)};
  Recorder r;
  EXPECT_EQ(run(x, r), 5);
  ASSERT_EQ(r.windows.size(), 1u);
  EXPECT_EQ(r.windows[0], (Bytes{0x11, 0x22, 0, 0, 0}));
  EXPECT_EQ(rb, (Bytes{0xFF, 0xFF, 0xFF}));
}

TEST(SpidevFrame, ZeroLengthTransfersSendNothingButCsChangeStillSplits) {
  Bytes a{1}, b{2};
  std::vector<spi_ioc_transfer> x{xfer(&a, nullptr, 1), xfer(nullptr, nullptr, 0, true), xfer(&b, nullptr, 1)};
  Recorder r;
  EXPECT_EQ(run(x, r), 2);
  ASSERT_EQ(r.windows.size(), 2u);
  EXPECT_EQ(r.windows[0], (Bytes{1}));
  EXPECT_EQ(r.windows[1], (Bytes{2}));
  std::vector<spi_ioc_transfer> empty{xfer(nullptr, nullptr, 0)};
  Recorder none;
  EXPECT_EQ(run(empty, none), 0);
  EXPECT_TRUE(none.windows.empty());
}

TEST(SpidevFrame, RefusedMessagesSendNothing) {
  Bytes a(8, 0x5A), b(8, 0xA5);
  {
    std::vector<spi_ioc_transfer> x{xfer(&a, nullptr, 8, true), xfer(&b, nullptr, 8)};
    x[1].bits_per_word = 16;  // the chips are byte-wide
    Recorder r;
    EXPECT_EQ(run(x, r), -EINVAL);
    EXPECT_TRUE(r.windows.empty());
  }
  {
    std::vector<spi_ioc_transfer> x{xfer(&a, nullptr, 8)};
    x[0].rx_nbits = 4;  // quad SPI
    Recorder r;
    EXPECT_EQ(run(x, r), -EINVAL);
  }
  {
    // The first window fits, the second does not: nothing is sent at all.
    std::vector<spi_ioc_transfer> x{xfer(&a, nullptr, 8, true), xfer(&a, nullptr, 8), xfer(&b, nullptr, 8)};
    Recorder r;
    EXPECT_EQ(run(x, r, 15), -EMSGSIZE);
    EXPECT_TRUE(r.windows.empty());
  }
  {
    std::vector<spi_ioc_transfer> x{xfer(&a, nullptr, 8)};
    x[0].bits_per_word = 8;
    Recorder r;
    r.fail = true;
    EXPECT_EQ(run(x, r), -EIO);
  }
}

// The windows against the emulated LAN9252: the register read a firmware
// splits into command + data transfers reads what one transaction reads.
struct Lan9252 {
  ManualClock clock;
  esc::Esc esc{esc::test::make_config(), clock};
  pdi_spi::EmulatedLan9252 chip{esc};
  static int window(void* ctx, std::uint8_t* buf, std::size_t len) {
    auto* self = static_cast<Lan9252*>(ctx);
    const Bytes tx(buf, buf + len);
    return self->chip.transfer(tx, std::span<std::uint8_t>(buf, len)) ? 0 : -1;
  }
};

TEST(SpidevFrame, SplitRegisterReadsOfTheEmulatedLan9252) {
  Lan9252 s;
  Bytes cmd{pdi_spi::lan9252::kInstrRead, 0x00, pdi_spi::lan9252::kByteTest}, data(4, 0xEE);
  Bytes cmd2{pdi_spi::lan9252::kInstrRead, 0x00, pdi_spi::lan9252::kIdRev}, data2(4, 0xEE);
  std::vector<spi_ioc_transfer> x{xfer(&cmd, nullptr, 3), xfer(nullptr, &data, 4, true), xfer(&cmd2, nullptr, 3),
                                  xfer(nullptr, &data2, 4)};
  std::vector<std::uint8_t> scratch(ECAT_PDI_MAX_PAYLOAD);
  EXPECT_EQ(spidev_run_message(x.data(), 4, scratch.data(), scratch.size(), &Lan9252::window, &s), 14);
  EXPECT_EQ(data, (Bytes{0x21, 0x43, 0x65, 0x87}));  // BYTE_TEST 0x87654321, least significant byte first
  EXPECT_EQ(data2, (Bytes{0x01, 0x00, 0x52, 0x92}));  // ID_REV 0x92520001
}

// Without the cs_change the second command's bytes are clocked as data of
// the first read (auto-increment): exactly what a LAN9252 does, so the
// framing matters.
TEST(SpidevFrame, WithoutCsChangeTheSecondCommandIsData) {
  Lan9252 s;
  Bytes cmd{pdi_spi::lan9252::kInstrRead, 0x00, pdi_spi::lan9252::kByteTest}, data(4), cmd2(3), rx2(3, 0xEE);
  cmd2 = {pdi_spi::lan9252::kInstrRead, 0x00, pdi_spi::lan9252::kIdRev};
  std::vector<spi_ioc_transfer> x{xfer(&cmd, nullptr, 3), xfer(nullptr, &data, 4), xfer(&cmd2, &rx2, 3)};
  std::vector<std::uint8_t> scratch(ECAT_PDI_MAX_PAYLOAD);
  EXPECT_EQ(spidev_run_message(x.data(), 3, scratch.data(), scratch.size(), &Lan9252::window, &s), 10);
  EXPECT_EQ(data, (Bytes{0x21, 0x43, 0x65, 0x87}));
  // Auto-increment: 0x0068-0x006A (not ID_REV), which the emulated chip reads as 0.
  EXPECT_EQ(rx2, (Bytes{0x00, 0x00, 0x00}));
}

constexpr gpio_line_map kMap{4, 5, 6, 1};

TEST(GpioEdges, IrqPinIsActiveLowByDefaultChoice) {
  EXPECT_EQ(gpio_irq_level(&kMap, 1), 0);
  EXPECT_EQ(gpio_irq_level(&kMap, 0), 1);
  gpio_line_map high = kMap;
  high.irq_active_low = 0;
  EXPECT_EQ(gpio_irq_level(&high, 1), 1);
  EXPECT_EQ(gpio_irq_level(&high, 0), 0);
}

TEST(GpioEdges, IrqChangesAndSyncPulses) {
  gpio_edge e[GPIO_MAX_EDGES];
  EXPECT_EQ(gpio_physical_edges(&kMap, 0, 0, 0, e), 0u);
  EXPECT_EQ(gpio_physical_edges(&kMap, 1, 1, 0, e), 0u);
  ASSERT_EQ(gpio_physical_edges(&kMap, 0, 1, 0, e), 1u);
  EXPECT_EQ(e[0].offset, 4u);
  EXPECT_EQ(e[0].id, static_cast<std::uint32_t>(GPIO_EDGE_FALLING));  // asserted: pulled low
  ASSERT_EQ(gpio_physical_edges(&kMap, 1, 0, 0, e), 1u);
  EXPECT_EQ(e[0].id, static_cast<std::uint32_t>(GPIO_EDGE_RISING));
  ASSERT_EQ(gpio_physical_edges(&kMap, 0, 1, ECAT_PDI_SYNC0 | ECAT_PDI_SYNC1, e), 5u);
  const std::uint32_t want[5][2] = {{4, GPIO_EDGE_FALLING}, {5, GPIO_EDGE_RISING}, {5, GPIO_EDGE_FALLING},
                                    {6, GPIO_EDGE_RISING}, {6, GPIO_EDGE_FALLING}};
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(e[i].offset, want[i][0]) << i;
    EXPECT_EQ(e[i].id, want[i][1]) << i;
  }
  ASSERT_EQ(gpio_physical_edges(&kMap, 0, 0, ECAT_PDI_SYNC1, e), 2u);
  EXPECT_EQ(e[0].offset, 6u);
}

TEST(GpioEdges, EventsFollowTheRequestedEdgesAndActiveLow) {
  const std::uint64_t in = GPIO_V2_LINE_FLAG_INPUT;
  EXPECT_EQ(gpio_event_for(in, GPIO_EDGE_RISING), 0u);  // no edge detection asked
  EXPECT_EQ(gpio_event_for(in | GPIO_V2_LINE_FLAG_EDGE_RISING, GPIO_EDGE_RISING),
            static_cast<std::uint32_t>(GPIO_V2_LINE_EVENT_RISING_EDGE));
  EXPECT_EQ(gpio_event_for(in | GPIO_V2_LINE_FLAG_EDGE_RISING, GPIO_EDGE_FALLING), 0u);
  EXPECT_EQ(gpio_event_for(in | GPIO_V2_LINE_FLAG_EDGE_FALLING, GPIO_EDGE_FALLING),
            static_cast<std::uint32_t>(GPIO_V2_LINE_EVENT_FALLING_EDGE));
  // Active low: the physical falling edge of an asserted IRQ is a logical rising one.
  const std::uint64_t low = in | GPIO_V2_LINE_FLAG_ACTIVE_LOW;
  EXPECT_EQ(gpio_event_for(low | GPIO_V2_LINE_FLAG_EDGE_RISING, GPIO_EDGE_FALLING),
            static_cast<std::uint32_t>(GPIO_V2_LINE_EVENT_RISING_EDGE));
  EXPECT_EQ(gpio_event_for(low | GPIO_V2_LINE_FLAG_EDGE_RISING, GPIO_EDGE_RISING), 0u);
  EXPECT_EQ(gpio_event_for(low | GPIO_V2_LINE_FLAG_EDGE_FALLING, GPIO_EDGE_RISING),
            static_cast<std::uint32_t>(GPIO_V2_LINE_EVENT_FALLING_EDGE));
}

}  // namespace
}  // namespace ecat::pdi_host::test
