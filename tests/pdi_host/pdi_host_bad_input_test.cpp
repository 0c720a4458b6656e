// A firmware that misbehaves on the PDI host's socket (issue 28, bad input):
// writes outside the ESC's memory, floods the socket, or vanishes in the
// middle of a message. Each gets what the chip would give it (writes past
// the process RAM and to read-only registers dropped, reads there 0, the
// ET1100's PDI error counter 0x030D for a broken SPI access) or is
// disconnected with its reason - and in every case the master's frames are
// still answered with the right working counter and data.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "esc/register_bits.hpp"
#include "esc/registers.hpp"
#include "tests/pdi_host/host_bench.hpp"

namespace ecat::test {
namespace {

namespace reg = esc::reg;

constexpr std::uint16_t kStation = 0x1001;  // the master's first station address

Bytes8 read_request(std::uint16_t address, std::uint16_t length) {
  return {ECAT_PDI_MSG_READ, 0, 4, 0, static_cast<std::uint8_t>(address), static_cast<std::uint8_t>(address >> 8),
          static_cast<std::uint8_t>(length), static_cast<std::uint8_t>(length >> 8)};
}

Bytes8 write_request(std::uint16_t address, const Bytes8& data) {
  Bytes8 m = {ECAT_PDI_MSG_WRITE, 0, static_cast<std::uint8_t>(data.size() + 2), 0,
              static_cast<std::uint8_t>(address), static_cast<std::uint8_t>(address >> 8)};
  m.insert(m.end(), data.begin(), data.end());
  return m;
}

// The master reads `n` bytes at `address` of the slave (FPRD); the
// network side works when this succeeds (WKC 1).
Bytes8 master_reads(HostBench& b, std::uint16_t address, std::size_t n) {
  Bytes8 out(n, 0xEE);
  auto r = b.p.master.fprd(kStation, address, out);
  EXPECT_TRUE(r) << "FPRD 0x" << std::hex << address;
  return out;
}

int attach(HostBench& b) {
  const int fd = b.connect_firmware();
  b.host->service(b.p.clock.now());
  EXPECT_EQ(HostBench::take(fd, kGreeting).size(), kGreeting);
  return fd;
}

// The default device has 8 KiB of process RAM (0x1000-0x2FFF): a write that
// runs past it keeps its bytes inside and drops the rest, a write wholly past
// it and one to read-only registers change nothing; each is answered as a
// write (82 00 00 00), the firmware stays attached, and the master reads what
// the ESC holds.
TEST(PdiHostBadInput, WritesOutsideTheEscMemoryAreDroppedAsOnTheChip) {
  HostBench b;
  ASSERT_TRUE(b.p.master.scan());
  esc::Esc& e = b.p.chain[0].esc();
  ASSERT_EQ(e.memory_size(), 0x3000u);
  const std::uint8_t type = e.memory()[reg::kType];
  const std::uint16_t dl_status = e.register_u16(reg::kDlStatus);
  const int fd = attach(b);
  HostBench::send(fd, write_request(0x2FFE, {0x11, 0x22, 0x33, 0x44}));  // 2 bytes in, 2 past the RAM
  HostBench::send(fd, write_request(0x8000, {0xAA, 0xBB}));              // past the RAM
  HostBench::send(fd, write_request(0xFFFE, {0xCC, 0xDD}));              // the last two addresses
  HostBench::send(fd, write_request(reg::kType, {0x55}));                // read-only: ESC type
  HostBench::send(fd, write_request(reg::kDlStatus, {0x00, 0x00}));      // read-only: DL status
  HostBench::send(fd, read_request(0x2FFE, 4));
  HostBench::send(fd, read_request(0xFFFE, 2));
  b.host->service(b.p.clock.now());
  const Bytes8 written = {0x82, 0, 0, 0};
  for (int i = 0; i < 5; ++i) EXPECT_EQ(HostBench::take(fd, 4), written) << "write " << i;
  EXPECT_EQ(HostBench::take(fd, 8), (Bytes8{0x81, 0, 4, 0, 0x11, 0x22, 0, 0}));
  EXPECT_EQ(HostBench::take(fd, 6), (Bytes8{0x81, 0, 2, 0, 0, 0}));
  EXPECT_TRUE(b.host->attached());
  EXPECT_EQ(b.host->stats().messages, 7u);
  EXPECT_EQ(b.host->stats().dropped, 0u);
  EXPECT_EQ(e.memory()[reg::kType], type);
  // Unchanged but for bit 1: the firmware's accesses fed the PDI watchdog.
  EXPECT_EQ(e.register_u16(reg::kDlStatus), static_cast<std::uint16_t>(dl_status | esc::bits::kDlPdiWatchdogOk));
  // The network side: the master reads the same, WKC 1 each.
  EXPECT_EQ(master_reads(b, 0x2FFE, 2), (Bytes8{0x11, 0x22}));
  EXPECT_EQ(master_reads(b, reg::kType, 1), (Bytes8{type}));
  ::close(fd);
}

// A write that would wrap past 0xFFFF cannot be clocked by any PDI: the
// message is malformed, the connection is closed with the reason, and the
// master goes on reading the ESC.
TEST(PdiHostBadInput, WriteWrappingPastTheAddressSpaceClosesTheConnectionOnly) {
  HostBench b;
  ASSERT_TRUE(b.p.master.scan());
  const int fd = attach(b);
  HostBench::send(fd, write_request(0xFFFF, {0x01, 0x02}));
  b.host->service(b.p.clock.now());
  EXPECT_FALSE(b.host->attached());
  EXPECT_EQ(b.log.back(), "pdi-host: firmware disconnected: WRITE of 2 bytes at 0xFFFF: past 0xFFFF");
  EXPECT_EQ(b.host->stats().dropped, 1u);
  EXPECT_EQ(HostBench::take(fd, 1).size(), 0u);  // closed
  auto st = b.p.master.read_al_status(0);
  ASSERT_TRUE(st);
  EXPECT_TRUE(st->is(master::AlState::Init));
  ::close(fd);
}

// On --pdi-chip et1100-spi a read clocked without its termination byte is
// an SPI interface error: the ESC counts it in 0x030D with the reason in
// 0x030E (0x10 read termination missing | CMD[2:1] 01 << 6), as the chip
// does; the connection stays, and the master reads the counter too.
TEST(PdiHostBadInput, BrokenEt1100SpiAccessCountsInThePdiErrorCounter) {
  HostBench b(pdi_host::PdiChip::Et1100Spi);
  ASSERT_TRUE(b.p.master.scan());
  esc::Esc& e = b.p.chain[0].esc();
  const int fd = attach(b);
  // Read with wait state of 0x0134 (2 bytes) without the 0xFF termination.
  HostBench::send(fd, {ECAT_PDI_MSG_SPI, 0, 5, 0, 0x09, 0xA3, 0xFF, 0x00, 0x00});
  b.host->service(b.p.clock.now());
  const Bytes8 reply = HostBench::take(fd, 9);
  ASSERT_EQ(reply.size(), 9u);
  EXPECT_EQ(Bytes8(reply.begin(), reply.begin() + 4), (Bytes8{0x83, 0, 5, 0}));
  EXPECT_TRUE(b.host->attached());
  EXPECT_EQ(e.memory()[reg::kPdiErrorCounter], 1);
  EXPECT_EQ(e.memory()[reg::kPdiErrorCode], 0x50);
  EXPECT_EQ(master_reads(b, reg::kPdiErrorCounter, 2), (Bytes8{0x01, 0x50}));
  ::close(fd);
}

// A firmware that sends requests and never reads the replies: each service
// answers at most kMessagesPerService of them (frames in between are
// answered), and once more than kMaxPendingOut bytes of replies wait the
// firmware is dropped with the reason. The master is answered throughout.
TEST(PdiHostBadInput, FloodingFirmwareIsBoundedPerServiceThenDropped) {
  HostBench b;
  ASSERT_TRUE(b.p.master.scan());
  const int fd = attach(b);
  // 100 TIME requests in one go: 64 answered, the rest wait (busy()).
  Bytes8 times;
  for (int i = 0; i < 100; ++i) times.insert(times.end(), {ECAT_PDI_MSG_TIME, 0, 0, 0});
  HostBench::send(fd, times);
  b.host->service(b.p.clock.now());
  EXPECT_EQ(b.host->stats().messages, pdi_host::PdiHost::kMessagesPerService);
  EXPECT_TRUE(b.host->busy());
  EXPECT_EQ(master_reads(b, reg::kAlStatus, 2), (Bytes8{0x01, 0x00}));  // a frame between two turns
  b.host->service(b.p.clock.now());
  EXPECT_EQ(b.host->stats().messages, 100u);
  EXPECT_FALSE(b.host->busy());
  EXPECT_EQ(HostBench::take(fd, 100 * 12).size(), 100u * 12);
  // 40 reads of 65535 bytes, not read back: 2.6 MB of replies, of which the
  // socket takes its send buffer (net.core.wmem_default, 208 KiB on Debian).
  Bytes8 reads;
  for (int i = 0; i < 40; ++i) {
    const Bytes8 r = read_request(0x0000, 0xFFFF);
    reads.insert(reads.end(), r.begin(), r.end());
  }
  HostBench::send(fd, reads);
  for (int turn = 0; turn < 10 && b.host->attached(); ++turn) b.host->service(b.p.clock.now());
  EXPECT_FALSE(b.host->attached());
  EXPECT_EQ(b.host->stats().dropped, 1u);
  EXPECT_EQ(b.host->stats().messages, 140u);
  const std::string& why = b.log.back();
  EXPECT_EQ(why.rfind("pdi-host: firmware disconnected: ", 0), 0u) << why;
  EXPECT_NE(why.find(" bytes of replies unread: the firmware does not read its socket"), std::string::npos) << why;
  EXPECT_EQ(master_reads(b, reg::kAlStatus, 2), (Bytes8{0x01, 0x00}));
  // The next firmware attaches.
  const int again = attach(b);
  EXPECT_TRUE(b.host->attached());
  ::close(again);
  ::close(fd);
}

// A firmware that dies half way through a message, with replies it never
// read (the kernel then resets the connection rather than closing it): the
// host sees the end, says so, and the half message is thrown away (the next
// firmware starts clean).
TEST(PdiHostBadInput, FirmwareGoneMidMessageWithRepliesUnreadLeavesTheNetworkRunning) {
  HostBench b;
  ASSERT_TRUE(b.p.master.scan());
  const int fd = attach(b);
  Bytes8 m = read_request(reg::kAlStatus, 2);
  Bytes8 half = read_request(reg::kAlStatus, 2);
  m.insert(m.end(), half.begin(), half.begin() + 5);  // header and one byte of the payload
  HostBench::send(fd, m);
  b.host->service(b.p.clock.now());
  EXPECT_EQ(b.host->stats().messages, 1u);
  ::close(fd);
  b.host->service(b.p.clock.now());
  EXPECT_FALSE(b.host->attached());
  EXPECT_EQ(b.log.back(), "pdi-host: firmware disconnected: the firmware closed its socket with replies unread");
  EXPECT_EQ(master_reads(b, reg::kAlStatus, 2), (Bytes8{0x01, 0x00}));
  // A new firmware's first request is read from its first byte.
  const int again = attach(b);
  HostBench::send(again, read_request(reg::kAlStatus, 2));
  b.host->service(b.p.clock.now());
  EXPECT_EQ(HostBench::take(again, 6), (Bytes8{0x81, 0, 2, 0, 0x01, 0x00}));
  ::close(again);
}

}  // namespace
}  // namespace ecat::test
