// The Linux side without hardware: the spidev ioctl argument, the GPIO v2
// line request, clear errors for devices that are missing or not SPI, and
// the --pdi parser.
#include <gtest/gtest.h>

#include "pdi_spi/gpio_irq_line.hpp"
#include "pdi_spi/pdi_spec.hpp"
#include "pdi_spi/spidev_bus.hpp"

namespace ecat::pdi_spi::test {
namespace {

TEST(Spidev, TransferArgumentDescribesOneFullDuplexTransaction) {
  std::uint8_t tx[7]{1, 2, 3, 4, 5, 6, 7};
  std::uint8_t rx[7]{};
  SpidevOptions o;
  o.speed_hz = 20'000'000;
  o.bits_per_word = 8;
  const spi_ioc_transfer t = make_spi_transfer(tx, rx, o);
  EXPECT_EQ(t.tx_buf, reinterpret_cast<std::uintptr_t>(tx));
  EXPECT_EQ(t.rx_buf, reinterpret_cast<std::uintptr_t>(rx));
  EXPECT_EQ(t.len, 7u);
  EXPECT_EQ(t.speed_hz, 20'000'000u);
  EXPECT_EQ(t.bits_per_word, 8);
  EXPECT_EQ(t.cs_change, 0);
  EXPECT_EQ(t.delay_usecs, 0);
  // SPI_IOC_MESSAGE(1): _IOW('k', 0, char[32]), one 32-byte transfer.
  EXPECT_EQ(sizeof(spi_ioc_transfer), 32u);
  EXPECT_EQ(SPI_IOC_MESSAGE(1), 0x40206B00u);
}

TEST(Spidev, MissingDeviceIsAClearError) {
  SpidevOptions o;
  o.device = "/nonexistent/spidev9.9";
  auto bus = SpidevBus::open(o);
  ASSERT_FALSE(bus);
  EXPECT_EQ(bus.error(), "/nonexistent/spidev9.9: cannot open: No such file or directory");
}

TEST(Spidev, NonSpiDeviceFailsAtTheModeIoctl) {
  SpidevOptions o;
  o.device = "/dev/null";
  auto bus = SpidevBus::open(o);
  ASSERT_FALSE(bus);
  EXPECT_EQ(bus.error().rfind("/dev/null: setting the SPI mode: ", 0), 0u) << bus.error();
}

TEST(GpioLine, RequestIsOneInputLineWithAssertionEdge) {
  GpioLineOptions o;
  o.offset = 25;
  const gpio_v2_line_request r = make_gpio_line_request(o);
  EXPECT_EQ(r.num_lines, 1u);
  EXPECT_EQ(r.offsets[0], 25u);
  EXPECT_STREQ(r.consumer, "ecat-slave");
  EXPECT_EQ(r.config.flags,
            GPIO_V2_LINE_FLAG_INPUT | GPIO_V2_LINE_FLAG_EDGE_RISING | GPIO_V2_LINE_FLAG_ACTIVE_LOW);
  EXPECT_EQ(r.config.num_attrs, 0u);
  o.active_low = false;
  EXPECT_EQ(make_gpio_line_request(o).config.flags, GPIO_V2_LINE_FLAG_INPUT | GPIO_V2_LINE_FLAG_EDGE_RISING);
}

TEST(GpioLine, MissingChipIsAClearError) {
  GpioLineOptions o;
  o.chip = "/nonexistent/gpiochip7";
  auto line = GpioIrqLine::open(o);
  ASSERT_FALSE(line);
  EXPECT_EQ(line.error(), "/nonexistent/gpiochip7: cannot open: No such file or directory");
}

TEST(PdiSpec, ParsesChipAndDevice) {
  auto a = parse_pdi_spec("lan9252:/dev/spidev0.0");
  ASSERT_TRUE(a);
  EXPECT_EQ(a->chip, SpiChip::Lan9252);
  EXPECT_EQ(a->device, "/dev/spidev0.0");
  auto b = parse_pdi_spec("et1100-spi:/dev/spidev1.2");
  ASSERT_TRUE(b);
  EXPECT_EQ(b->chip, SpiChip::Et1100);
  EXPECT_EQ(parse_pdi_spec("lan9252").error(), "'lan9252': expected CHIP:SPIDEV, e.g. lan9252:/dev/spidev0.0");
  EXPECT_EQ(parse_pdi_spec("ax58100:/dev/spidev0.0").error(), "unknown PDI chip 'ax58100' (lan9252 or et1100-spi)");
}

}  // namespace
}  // namespace ecat::pdi_spi::test
