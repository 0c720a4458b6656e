// The ESC of a slave whose firmware is another process (SlaveOptions::
// external_firmware): the master's mailbox accesses raise and clear the SM
// events in 0x0220 that the firmware waits for, as on silicon - and reading
// an SM's status register does not clear them (SOES reads both mailbox
// statuses before it tests the SM1 bit; the emulation used to clear it).
#include <gtest/gtest.h>

#include "esc/register_bits.hpp"
#include "esc/registers.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

constexpr std::uint32_t kSm0Event = 1u << esc::bits::kAlEventSmShift;

TEST(PdiHostEsc, MasterMailboxWriteRaisesTheSm0EventForTheExternalFirmware) {
  InProcess p;
  auto d = esi::load_default_device();
  ASSERT_TRUE(d);
  slave::SlaveOptions o;
  o.external_firmware = true;
  p.add(*d, o);
  ASSERT_TRUE(p.master.scan());
  ASSERT_TRUE(p.master.configure_mailbox(0));
  esc::Esc& e = p.chain[0].esc();
  // The firmware acknowledges PreOp itself (here: the test, on the PDI).
  e.write_u16(esc::reg::kAlStatus, 0x0002);
  EXPECT_EQ(e.al_event_request() & kSm0Event, 0u);
  const std::uint8_t payload[10] = {0x00, 0x20, 0x40, 0x00, 0x10, 0x00};
  ASSERT_TRUE(p.master.mailbox_send(0, 3, payload));
  EXPECT_EQ(e.al_event_request() & kSm0Event, kSm0Event);
  // Reading the SM0 status register (SOES's ESC_SMstatus) leaves the event:
  // only an access to the buffer clears it (Section II 0x0220 bit 8+n mirrors 0x0805 bits 0/1).
  EXPECT_EQ(e.read_u8(static_cast<std::uint16_t>(esc::reg::sync_manager(0) + esc::reg::sm::kStatus)) & 0x09, 0x09);
  EXPECT_EQ(e.al_event_request() & kSm0Event, kSm0Event);
  // SOES's mailbox read: header, data, last byte (releases the buffer).
  std::uint8_t b[128]{};
  e.read(0x1000, std::span(b, 6));
  e.read(0x1006, std::span(b, 10));
  e.read(0x107F, std::span(b, 1));
  EXPECT_EQ(e.al_event_request() & kSm0Event, 0u);
  std::uint8_t reply[16] = {0x0A, 0, 0, 0, 0, 0x13};
  e.write(0x1080, reply);
  e.write(0x10FF, std::span(b, 1));
  auto got = p.master.mailbox_receive(0, std::chrono::milliseconds(10));
  ASSERT_TRUE(got) << static_cast<int>(got.error());
  EXPECT_EQ(e.al_event_request() & (kSm0Event << 1), kSm0Event << 1);
  (void)e.read_u8(static_cast<std::uint16_t>(esc::reg::sync_manager(1) + esc::reg::sm::kStatus));
  EXPECT_EQ(e.al_event_request() & (kSm0Event << 1), kSm0Event << 1);
  // SOES acknowledges the read by writing the first byte of SM1: cleared.
  e.write(0x1080, std::span(b, 1));
  EXPECT_EQ(e.al_event_request() & (kSm0Event << 1), 0u);
}

}  // namespace
}  // namespace ecat::test
