// Issue 18, timing honesty: what one application cycle costs on the SPI
// bus, counted over the emulated chips (every transaction the firmware
// makes between two master cycles in Op, SM-synchronous), for the CSP drive
// (generic servo, 19/25-byte PDOs) and a 32-channel I/O slave (4/4 bytes).
// The counts are exact and pinned here; docs/real-esc.md and
// docs/performance-log.md turn them into time at 10/20/30 MHz.
#include <gtest/gtest.h>

#include <cstdio>

#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

struct Cost {
  std::uint64_t transactions;  // per application cycle
  std::uint64_t bytes;
};

// The cost of one cycle in Op after bring-up; every cycle must cost the
// same (checked: the totals are exact multiples).
Cost cost_per_cycle(const std::string& file, slave::PdiKind pdi, pdi_spi::Lan9252Options lan = {}) {
  InProcess p;
  auto d = esi::load_device_file(file);
  if (!d) throw std::runtime_error(d.error().to_string());
  slave::SlaveOptions o;
  o.pdi = pdi;
  o.lan9252 = lan;
  p.add(std::move(*d), o);
  EXPECT_EQ(p.bring_up(), "");
  for (int i = 0; i < 20; ++i) EXPECT_TRUE(p.cycle_once(std::chrono::milliseconds(1)));
  slave::VirtualSlave& s = p.chain[0];
  s.spi_pdi()->reset_counters();
  const std::uint64_t before = s.status().application_cycles;
  for (int i = 0; i < 200; ++i) EXPECT_TRUE(p.cycle_once(std::chrono::milliseconds(1)));
  const std::uint64_t cycles = s.status().application_cycles - before;
  EXPECT_GE(cycles, 200u);
  EXPECT_EQ(s.spi_chip()->violations(), 0u);
  const auto& c = s.spi_pdi()->counters();
  EXPECT_EQ(c.transactions % cycles, 0u) << c.transactions << " transactions in " << cycles << " cycles";
  EXPECT_EQ(c.bytes % cycles, 0u) << c.bytes << " bytes in " << cycles << " cycles";
  const Cost cost{c.transactions / cycles, c.bytes / cycles};
  std::printf("[ cost     ] %s over %s: %llu transactions, %llu bytes per cycle\n", file.c_str(),
              pdi == slave::PdiKind::Lan9252 ? "LAN9252" : "ET1100 SPI",
              static_cast<unsigned long long>(cost.transactions), static_cast<unsigned long long>(cost.bytes));
  return cost;
}

std::string servo() { return std::string(ECAT_SOURCE_DIR) + "/xml/devices/generic-servo.xml"; }
std::string io32() { return std::string(ECAT_SOURCE_DIR) + "/tests/data/devices/io-32ch.xml"; }

// The firmware's cycle: AL event request 0x0220 (4 bytes), SM2 outputs,
// SM3 inputs - one access each. Generic servo: SM2 14 bytes, SM3 16 bytes.
// LAN9252: 0x0220 is a CSR read (command, poll, data: 3 x 7 bytes), each
// SM buffer a PRAM command (ADDR_LEN, CMD, poll: 3 x 7 bytes) and one FIFO
// burst of 3 + whole DWORDs.
TEST(SpiCycleCost, CspDriveOverLan9252) {
  const Cost c = cost_per_cycle(servo(), slave::PdiKind::Lan9252);
  EXPECT_EQ(c.transactions, 11u);
  EXPECT_EQ(c.bytes, 21u + (21u + 3u + 16u) + (21u + 3u + 16u));
}

// FAST READ, ADDR_LEN + CMD in one write, CSR data read without polling
// (Microchip's driver): 0x0220 = 7 + 8, SM2 = 11 + 8 + 4 + 16, SM3 = 11 +
// 8 + 3 + 16.
TEST(SpiCycleCost, CspDriveOverLan9252Lean) {
  const Cost c = cost_per_cycle(servo(), slave::PdiKind::Lan9252,
                                {.fast_read = true, .burst_setup = true, .skip_csr_poll = true});
  EXPECT_EQ(c.transactions, 8u);
  EXPECT_EQ(c.bytes, 15u + 39u + 38u);
}

// ET1100: 0x0220 rides on the address phase (2 + 1 wait state + 2), SM2
// 2 + 1 + 14, SM3 2 + 16.
TEST(SpiCycleCost, CspDriveOverEt1100) {
  const Cost c = cost_per_cycle(servo(), slave::PdiKind::Et1100Spi);
  EXPECT_EQ(c.transactions, 3u);
  EXPECT_EQ(c.bytes, 5u + 17u + 18u);
}

TEST(SpiCycleCost, Io32OverLan9252) {
  const Cost c = cost_per_cycle(io32(), slave::PdiKind::Lan9252);
  EXPECT_EQ(c.transactions, 11u);
  EXPECT_EQ(c.bytes, 21u + (21u + 3u + 4u) + (21u + 3u + 4u));
}

TEST(SpiCycleCost, Io32OverLan9252Lean) {
  const Cost c = cost_per_cycle(io32(), slave::PdiKind::Lan9252,
                                {.fast_read = true, .burst_setup = true, .skip_csr_poll = true});
  EXPECT_EQ(c.transactions, 8u);
  EXPECT_EQ(c.bytes, 15u + 27u + 26u);
}

TEST(SpiCycleCost, Io32OverEt1100) {
  const Cost c = cost_per_cycle(io32(), slave::PdiKind::Et1100Spi);
  EXPECT_EQ(c.transactions, 3u);
  EXPECT_EQ(c.bytes, 5u + 7u + 6u);
}

}  // namespace
}  // namespace ecat::test
