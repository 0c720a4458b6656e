// The emulated ET1100 SPI slave raises the ESC's PDI error counter 0x030D
// and error code 0x030E as Section II describes them (§2.9.4 "PDI0 error
// counter": counts each access with an interface error, stops at 0xFF, a
// write of 0x030D clears 0x030D and 0x030E:0x030F; §2.9.5.1 "SPI slave
// error code": bits 2:0 clocks of the access modulo 8, 4 read termination
// missing, 5 access continued after the termination byte, 7:6 CMD[2:1]).
// Every access goes through the chip's SPI side as a host clocks it, and
// the host reads 0x030D/0x030E back the same way.
#include <gtest/gtest.h>

#include "esc/esc.hpp"
#include "esc/registers.hpp"
#include "pdi_spi/emulated_et1100_spi.hpp"
#include "pdi_spi/emulated_lan9252.hpp"
#include "pdi_spi/et1100_spi_pdi.hpp"
#include "pdi_spi/lan9252_pdi.hpp"
#include "recording_bus.hpp"
#include "tests/esc/esc_fixture.hpp"

namespace ecat::pdi_spi::test {
namespace {

using esc::test::ap;
namespace reg = esc::reg;

struct Chip {
  esc::test::Line line{1};
  EmulatedEt1100Spi spi{line[0]};

  Bytes clock(const Bytes& tx) {
    Bytes rx(tx.size(), 0xEE);
    EXPECT_TRUE(spi.transfer(tx, rx));
    return rx;
  }
  Bytes clock_bits(const Bytes& tx, std::size_t clocks) {
    Bytes rx(tx.size(), 0xEE);
    EXPECT_TRUE(spi.transfer_clocks(tx, rx, clocks));
    return rx;
  }
  // 0x030D and 0x030E as the host reads them: read with wait state at
  // 0x030D (A[12:5] = 0x18, A[4:0] << 3 | 3 = 0x6B), two bytes, terminated.
  std::pair<unsigned, unsigned> pdi_error() {
    const Bytes rx = clock({0x18, 0x6B, 0xFF, 0x00, 0xFF});
    return {rx[3], rx[4]};
  }
};

constexpr unsigned kCmdReadWs = 0x3 >> 1 << 6;  // CMD[2:1] of 011 in bits 7:6: 0x40
constexpr unsigned kCmdWrite = 0x4 >> 1 << 6;   // CMD[2:1] of 100: 0x80

// Read with wait state of 0x0134 (AL status code, 2 bytes) without the
// 0xFF termination byte: counted, code 0x10 | CMD 01.
TEST(Et1100PdiError, ReadWithoutTerminationByte) {
  Chip c;
  c.line[0].write_u16(0x0134, 0x1234);
  const Bytes rx = c.clock({0x09, 0xA3, 0xFF, 0x00, 0x00});
  EXPECT_EQ(rx[3], 0x34);  // the clocked bytes are still read
  EXPECT_EQ(rx[4], 0x12);
  EXPECT_EQ(c.pdi_error(), std::make_pair(1u, 0x10u | kCmdReadWs));
  EXPECT_EQ(c.line[0].memory()[reg::kPdiErrorCounter], 1);
  EXPECT_EQ(c.line[0].memory()[reg::kPdiErrorCode], 0x50);
}

// Bytes clocked after the termination byte: code 0x20 | CMD. Command 010
// (read without wait state) has the same CMD[2:1] = 01 as 011.
TEST(Et1100PdiError, AccessContinuedAfterTermination) {
  Chip c;
  c.clock({0x09, 0xA3, 0xFF, 0xFF, 0x00});
  EXPECT_EQ(c.pdi_error(), std::make_pair(1u, 0x20u | kCmdReadWs));
  c.clock({0x09, 0xA2, 0xFF, 0x00, 0x00});  // command 010: terminated at the first data byte
  EXPECT_EQ(c.pdi_error(), std::make_pair(2u, 0x60u));
}

// 3-byte addressing: the code carries the command of byte 2 (the access's
// read), not the address-extension command 110 of byte 1.
TEST(Et1100PdiError, ThreeByteAddressCarriesTheAccessCommand) {
  Chip c;
  const Bytes rx = c.clock({0x09, 0xA6, 0x0C, 0xFF, 0x00, 0x00});
  std::uint8_t al[3];
  c.line[0].read(0x0220, al);
  EXPECT_EQ(rx[0], al[0]);
  EXPECT_EQ(rx[2], al[2]);  // 0x0222 on the third address byte
  EXPECT_EQ(c.pdi_error(), std::make_pair(1u, 0x10u | kCmdReadWs));
}

// A write to user RAM 0x0F80 (A[12:5] = 0x7C, A[4:0] << 3 | 4 = 0x04) of 2
// bytes and 4 more clocks: bits 2:0 = 36 mod 8 = 4, CMD 10; the two whole
// bytes are written, the incomplete third is not.
TEST(Et1100PdiError, WriteWithIncompleteLastByte) {
  Chip c;
  c.clock_bits({0x7C, 0x04, 0x34, 0x12, 0xA0}, 36);
  EXPECT_EQ(c.line[0].memory()[0x0F80], 0x34);
  EXPECT_EQ(c.line[0].memory()[0x0F81], 0x12);
  EXPECT_EQ(c.line[0].memory()[0x0F82], 0);
  EXPECT_EQ(c.pdi_error(), std::make_pair(1u, 0x04u | kCmdWrite));
}

// A read whose last byte has 4 clocks: clocks 36 mod 8 = 4, and its MOSI
// bits 1111 are not a whole termination byte: 0x04 | 0x10 | CMD.
TEST(Et1100PdiError, ReadWithIncompleteLastByte) {
  Chip c;
  c.clock_bits({0x09, 0xA3, 0xFF, 0x00, 0xFF}, 36);
  EXPECT_EQ(c.pdi_error(), std::make_pair(1u, 0x14u | kCmdReadWs));
}

// SPI_SEL released after 12 clocks, inside the address phase: nothing is
// accessed; the command bits were never clocked (read as 0), so the code
// is the clock count alone.
TEST(Et1100PdiError, AccessEndingInsideTheAddressPhase) {
  Chip c;
  c.line[0].write_u16(0x0134, 0x1234);
  c.clock_bits({0x09, 0xA4}, 12);
  EXPECT_EQ(c.line[0].read_u16(0x0134), 0x1234);
  EXPECT_EQ(c.pdi_error(), std::make_pair(1u, 0x04u));
}

// The counter stops at 0xFF; the code is the reason of the last error.
TEST(Et1100PdiError, CounterSaturatesAndCodeIsTheLastReason) {
  Chip c;
  for (int i = 0; i < 300; ++i) c.clock({0x09, 0xA3, 0xFF, 0x00, 0x00});
  EXPECT_EQ(c.pdi_error(), std::make_pair(0xFFu, 0x50u));
  c.clock_bits({0x09, 0xA4, 0x00, 0x80}, 25);
  EXPECT_EQ(c.pdi_error(), std::make_pair(0xFFu, 0x01u | kCmdWrite));
}

// Only the master clears: an ECAT write of 0x030D clears 0x030D and
// 0x030E (Section II §2.9.4 note); the PDI (r/-) cannot.
TEST(Et1100PdiError, EcatWriteOf030DClearsCounterAndCode) {
  Chip c;
  c.clock({0x09, 0xA3, 0xFF, 0x00, 0x00});
  c.clock({0x09, 0xA3, 0xFF, 0xFF, 0x00});
  EXPECT_EQ(esc::test::transact(c.line.segment, Command::Aprd, ap(0, reg::kPdiErrorCounter), 2).data,
            (esc::test::Data{2, 0x60}));
  c.clock({0x18, 0x6C, 0x00});  // the host writes 0x030D: ignored
  EXPECT_EQ(c.pdi_error(), std::make_pair(2u, 0x60u));
  EXPECT_EQ(esc::test::transact(c.line.segment, Command::Apwr, ap(0, reg::kPdiErrorCounter), esc::test::Data{0}).wkc,
            1);
  EXPECT_EQ(c.pdi_error(), std::make_pair(0u, 0u));
  EXPECT_EQ(esc::test::transact(c.line.segment, Command::Aprd, ap(0, reg::kPdiErrorCounter), 2).data,
            (esc::test::Data{0, 0}));
}

// Framing faults that Section II gives no reason bit for stay out of the
// counter (they count in violations() only): a reserved command, a wait-
// state byte other than 0xFF, MOSI other than 0x00 before the termination,
// an access of whole bytes that ends inside the address phase.
TEST(Et1100PdiError, FaultsWithoutAReasonBitAreNotCounted) {
  Chip c;
  c.clock({0x09, 0xA1, 0x00});              // reserved command 001
  c.clock({0x09, 0xA3, 0x00, 0x00, 0xFF});  // wait-state byte 0x00
  c.clock({0x09, 0xA3, 0xFF, 0x55, 0xFF});  // MOSI 0x55 inside the data phase
  c.clock({0x09});                          // 8 clocks
  EXPECT_EQ(c.spi.violations(), 4u);
  EXPECT_EQ(c.pdi_error(), std::make_pair(0u, 0u));
}

// A read of 0 data bytes and a NOP are complete accesses.
TEST(Et1100PdiError, AddressPhaseOnlyAccessesAreNotErrors) {
  Chip c;
  c.clock({0x09, 0xA2});        // read, no data phase
  c.clock({0x09, 0xA3, 0xFF});  // read with wait state, no data
  c.clock({0x00, 0x00});        // NOP
  EXPECT_EQ(c.spi.violations(), 0u);
  EXPECT_EQ(c.pdi_error(), std::make_pair(0u, 0u));
}

// The backend's accesses in every option (wait state or not, 2- or 3-byte
// addressing, the 0x0220 piggyback, bursts into process RAM above 0x1FFF)
// never raise the PDI error counter.
TEST(Et1100PdiError, BackendAccessesNeverRaiseIt) {
  for (const bool wait_state : {true, false}) {
    for (const bool three_byte : {true, false}) {
      Chip c;
      Et1100SpiPdi pdi(c.spi, Et1100SpiOptions{wait_state, three_byte});
      Bytes data(300);
      for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<std::uint8_t>(i * 7);
      Bytes back(data.size());
      for (const std::uint16_t at : {std::uint16_t{0x1F80}, std::uint16_t{0x2100}}) {  // 2- and 3-byte phases
        pdi.write(at, data);
        pdi.read(at, back);
        EXPECT_EQ(back, data);
      }
      Bytes al(4), one(1), two(2);
      pdi.read(0x0220, al);
      pdi.read(0x0220, two);  // address phase alone (NOP)
      pdi.read(0x0134, two);
      pdi.read(0x0135, one);
      pdi.write(0x0F80, data);  // user RAM
      EXPECT_FALSE(pdi.failed()) << pdi.error();
      EXPECT_EQ(c.spi.violations(), 0u);
      EXPECT_EQ(c.line[0].memory()[reg::kPdiErrorCounter], 0) << wait_state << three_byte;
      EXPECT_EQ(c.line[0].memory()[reg::kPdiErrorCode], 0);
    }
  }
}

// The LAN9252's host SPI is its own front end: its framing faults do not
// reach the ESC core's PDI, so 0x030D/0x030E stay 0 (the data sheet
// sources found describe no path from one to the other; docs/real-esc.md).
TEST(Lan9252PdiError, HostFramingFaultsDoNotTouchTheCoreCounter) {
  esc::test::Line line(1);
  EmulatedLan9252 chip(line[0]);
  const auto clock = [&](const Bytes& tx) {
    Bytes rx(tx.size());
    chip.transfer(tx, rx);
  };
  clock({0x03, 0x00, 0x00, 0, 0, 0, 0});              // FIFO read without command
  clock({0x3B, 0x00, 0x00, 0});                       // instruction not emulated
  clock({0x02, 0x03, 0x04, 0x02, 0x00, 0x04, 0xC0});  // CSR size 4 at an unaligned address
  EXPECT_EQ(chip.violations(), 6u);
  Lan9252Pdi pdi(chip);
  Bytes counter(2);
  pdi.read(reg::kPdiErrorCounter, counter);
  EXPECT_FALSE(pdi.failed()) << pdi.error();
  EXPECT_EQ(counter, (Bytes{0, 0}));
  EXPECT_EQ(line[0].memory()[reg::kPdiErrorCounter], 0);
}

}  // namespace
}  // namespace ecat::pdi_spi::test
