// The emulated LAN9252 and ET1100 SPI slaves: exact MISO bytes for exact
// MOSI bytes, framing violations counted, and each backend over its
// emulated chip against the ESC accessed directly (same operations on two
// identical ESCs: same results, same memory, same IRQ).
#include <gtest/gtest.h>

#include <random>

#include "common/le.hpp"
#include "esc/esc.hpp"
#include "pdi_spi/emulated_et1100_spi.hpp"
#include "pdi_spi/emulated_lan9252.hpp"
#include "pdi_spi/et1100_spi_pdi.hpp"
#include "pdi_spi/lan9252_pdi.hpp"
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

TEST(EmulatedLan9252, SystemRegistersAnswerByteExact) {
  Silicon s;
  EmulatedLan9252 chip(s.esc);
  EXPECT_EQ(clock_through(chip, {0x03, 0x00, 0x64, 0, 0, 0, 0}), (Bytes{0, 0, 0, 0x21, 0x43, 0x65, 0x87}));
  EXPECT_EQ(clock_through(chip, {0x0B, 0x00, 0x74, 0, 0, 0, 0, 0}), (Bytes{0, 0, 0, 0, 0, 0, 0, 0x08}));
  // A 2-byte read from the middle of BYTE_TEST.
  EXPECT_EQ(clock_through(chip, {0x03, 0x00, 0x66, 0, 0}), (Bytes{0, 0, 0, 0x65, 0x87}));
  EXPECT_EQ(chip.violations(), 0u);
}

// ESC type register 0x0000 through ECAT_CSR_CMD / ECAT_CSR_DATA.
TEST(EmulatedLan9252, CsrReadReachesTheEscCore) {
  Silicon s;
  EmulatedLan9252 chip(s.esc);
  clock_through(chip, {0x02, 0x03, 0x04, 0x00, 0x00, 0x04, 0xC0});
  EXPECT_EQ(clock_through(chip, {0x03, 0x03, 0x04, 0, 0, 0, 0}), (Bytes{0, 0, 0, 0x00, 0x00, 0x04, 0x40}));
  const std::uint32_t expected = load_le<std::uint32_t>(s.esc.memory());
  const Bytes rx = clock_through(chip, {0x03, 0x03, 0x00, 0, 0, 0, 0});
  EXPECT_EQ(load_le<std::uint32_t>(rx.data() + 3), expected);
  // Size 4 at an address that is not DWORD-aligned is refused.
  clock_through(chip, {0x02, 0x03, 0x04, 0x02, 0x00, 0x04, 0xC0});
  EXPECT_EQ(chip.violations(), 1u);
}

TEST(EmulatedLan9252, FifoWithoutCommandIsAViolation) {
  Silicon s;
  EmulatedLan9252 chip(s.esc);
  clock_through(chip, {0x03, 0x00, 0x00, 0, 0, 0, 0});
  clock_through(chip, {0x02, 0x00, 0x20, 1, 2, 3, 4});
  clock_through(chip, {0x3B, 0x00, 0x00, 0});  // dual-output read: not emulated
  EXPECT_EQ(chip.violations(), 9u);
}

// The pin follows INT_STS.ECAT_INT (AL event request & mask) only once
// INT_EN.ECAT_INT and IRQ_CFG.IRQ_EN are set; the master's AL control
// write raises it, the PDI's read of 0x0120 drops it.
TEST(EmulatedLan9252, IrqPinNeedsIrqEnAndIntEn) {
  esc::test::Line line(1);
  esc::Esc& esc = line[0];
  EmulatedLan9252 chip(esc);
  esc.write_u32(0x0204, 0x00000001);  // AL event mask: AL control
  esc::test::transact(line.segment, Command::Apwr, esc::test::ap(0, 0x0120), esc::test::le16(0x0002));
  ASSERT_TRUE(esc.irq());
  EXPECT_FALSE(chip.irq_pin());
  clock_through(chip, {0x02, 0x00, 0x5C, 0x01, 0, 0, 0});  // INT_EN.ECAT_INT
  EXPECT_FALSE(chip.irq_pin());                            // IRQ_EN still 0
  clock_through(chip, {0x02, 0x00, 0x54, 0x01, 0x01, 0, 0});
  EXPECT_TRUE(chip.irq_pin());
  EXPECT_EQ(clock_through(chip, {0x03, 0x00, 0x58, 0, 0, 0, 0}), (Bytes{0, 0, 0, 0x01, 0, 0, 0}));
  (void)esc.read_u16(0x0120);
  EXPECT_FALSE(chip.irq_pin());
  EXPECT_EQ(clock_through(chip, {0x03, 0x00, 0x58, 0, 0, 0, 0}), (Bytes{0, 0, 0, 0, 0, 0, 0}));
}

TEST(EmulatedEt1100Spi, IrqPinIsTheEscIrq) {
  esc::test::Line line(1);
  EmulatedEt1100Spi chip(line[0]);
  line[0].write_u32(0x0204, 0x00000001);
  EXPECT_FALSE(chip.irq_pin());
  esc::test::transact(line.segment, Command::Apwr, esc::test::ap(0, 0x0120), esc::test::le16(0x0002));
  EXPECT_TRUE(chip.irq_pin());
  // Every access returns the AL event request in its address phase.
  EXPECT_EQ(clock_through(chip, {0x00, 0x00}), (Bytes{0x01, 0x00}));
}

TEST(EmulatedEt1100Spi, ReadReturnsAlEventThenData) {
  Silicon s;
  EmulatedEt1100Spi chip(s.esc);
  s.esc.write_u16(0x0134, 0x1234);  // AL status code, PDI-writable
  const Bytes rx = clock_through(chip, {0x09, 0xA3, 0xFF, 0x00, 0xFF});
  std::uint8_t al[2];
  s.esc.read(0x0220, al);
  EXPECT_EQ(rx, (Bytes{al[0], al[1], 0xFF, 0x34, 0x12}));
  EXPECT_EQ(chip.violations(), 0u);
}

TEST(EmulatedEt1100Spi, FramingViolationsAreCounted) {
  Silicon s;
  EmulatedEt1100Spi chip(s.esc);
  clock_through(chip, {0x09, 0xA3, 0xFF, 0x00, 0x00});        // no termination
  clock_through(chip, {0x09, 0xA3, 0xFF, 0xFF, 0x00});        // bytes after it
  clock_through(chip, {0x09, 0xA3, 0x00, 0x00, 0xFF});        // wait state not 0xFF
  clock_through(chip, {0x09, 0xA1});                          // reserved command 1
  clock_through(chip, {0x09});                                // runt
  EXPECT_EQ(chip.violations(), 5u);
}

// Random accesses over registers, SM-free process RAM and unaligned spans:
// the backend over its emulated chip leaves the ESC exactly as direct PDI
// accesses do, and reads the same bytes.
template <typename Backend, typename Chip>
void compare_with_direct(std::uint32_t seed) {
  Silicon direct;
  Silicon spi;
  Chip chip(spi.esc);
  Backend backend(chip);
  std::mt19937 rng(seed);
  auto pick = [&](std::uint32_t lo, std::uint32_t hi) { return std::uniform_int_distribution<std::uint32_t>(lo, hi)(rng); };
  for (int i = 0; i < 400; ++i) {
    // Registers the PDI may write without side effects (AL status code,
    // AL event mask, user RAM) and process RAM.
    static constexpr std::uint16_t kAreas[] = {0x0134, 0x0204, 0x0F80, 0x1000, 0x1003, 0x17F0};
    const std::uint16_t base = kAreas[pick(0, 5)];
    const auto address = static_cast<std::uint16_t>(base + (base >= 0x0F80 ? pick(0, 40) : 0));
    const std::size_t length = base >= 0x0F80 ? pick(1, 70) : (base == 0x0134 ? 2 : 4);
    Bytes data(length);
    for (auto& b : data) b = static_cast<std::uint8_t>(pick(0, 255));
    if (pick(0, 1) == 0) {
      direct.esc.write(address, data);
      backend.write(address, data);
    } else {
      Bytes a(length), b(length);
      direct.esc.read(address, a);
      backend.read(address, b);
      ASSERT_EQ(a, b) << "read at 0x" << std::hex << address;
    }
  }
  ASSERT_FALSE(backend.failed()) << backend.error();
  EXPECT_EQ(chip.violations(), 0u);
  for (std::size_t a = 0; a < 0x1800; ++a) {
    if (a >= 0x0400 && a < 0x0F80) continue;  // watchdog/DC timing of the access
    ASSERT_EQ(direct.esc.memory()[a], spi.esc.memory()[a]) << "at 0x" << std::hex << a;
  }
}

TEST(SpiBackendOverEmulatedChip, Lan9252MatchesDirectAccess) {
  for (std::uint32_t seed : {1u, 2u, 3u}) compare_with_direct<Lan9252Pdi, EmulatedLan9252>(seed);
}

TEST(SpiBackendOverEmulatedChip, Et1100MatchesDirectAccess) {
  for (std::uint32_t seed : {1u, 2u, 3u}) compare_with_direct<Et1100SpiPdi, EmulatedEt1100Spi>(seed);
}

TEST(SpiBackendOverEmulatedChip, Lan9252InitOverTheEmulatedChip) {
  Silicon s;
  EmulatedLan9252 chip(s.esc);
  Lan9252Pdi pdi(chip);
  ASSERT_TRUE(pdi.init()) << pdi.error();
  EXPECT_EQ(pdi.read_system(0x0050), EmulatedLan9252::kIdRevValue);
  EXPECT_EQ(chip.violations(), 0u);
}

}  // namespace
}  // namespace ecat::pdi_spi::test
