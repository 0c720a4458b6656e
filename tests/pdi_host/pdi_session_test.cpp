// The PDI host protocol on bytes (pdi_host/pdi_session.hpp): the exact
// replies to READ, WRITE, TIME, LINES and SPI, the lines notification when
// the AL event request changes, and malformed messages refused with their
// reason (docs/pdi-host.md).
#include <gtest/gtest.h>

#include <vector>

#include "esc/register_bits.hpp"
#include "esc/registers.hpp"
#include "pdi_host/pdi_session.hpp"
#include "pdi_spi/emulated_lan9252.hpp"
#include "pdi_spi/lan9252_registers.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

using Bytes8 = std::vector<std::uint8_t>;

struct Bench {
  Bench() {
    auto d = esi::load_default_device();
    if (!d) throw std::runtime_error("default device");
    slave::SlaveOptions o;
    o.external_firmware = true;
    p.add(*d, o);
  }
  esc::Esc& esc() { return p.chain[0].esc(); }
  InProcess p;
};

// Runs `in` through the session; returns the replies (the error, if any, in `error`).
Bytes8 run(pdi_host::PdiSession& s, Bytes8 in, std::string* error = nullptr) {
  Bytes8 out;
  auto r = s.handle(in, out, 100);
  if (!r && error) *error = r.error();
  if (r) {
    EXPECT_TRUE(in.empty());
  }
  return out;
}

TEST(PdiSession, GreetsWithHelloVersionChipAndTheLines) {
  Bench b;
  b.p.clock.set(Nanoseconds{0x0102030405060708});
  pdi_host::PdiSession s(b.esc(), pdi_host::PdiChip::Direct, nullptr, b.p.clock);
  Bytes8 out;
  s.greet(out);
  const Bytes8 want = {0xC0, 0, 4, 0, 1, 0, 0, 0,                                  // HELLO v1, direct
                       0xC1, 0, 20, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,          // no event, mask 0, IRQ low
                       0x08, 0x07, 0x06, 0x05, 0x04, 0x03, 0x02, 0x01};             // time
  EXPECT_EQ(out, want);
}

TEST(PdiSession, ReadAndWriteRepliesAreExact) {
  Bench b;
  pdi_host::PdiSession s(b.esc(), pdi_host::PdiChip::Direct, nullptr, b.p.clock);
  // WRITE 3 bytes at 0x1F00 (process RAM outside every SM), then READ them back with one byte each side.
  EXPECT_EQ(run(s, {0x02, 0, 5, 0, 0x00, 0x1F, 0xAA, 0xBB, 0xCC}), (Bytes8{0x82, 0, 0, 0}));
  EXPECT_EQ(run(s, {0x01, 0, 4, 0, 0xFF, 0x1E, 5, 0}), (Bytes8{0x81, 0, 5, 0, 0x00, 0xAA, 0xBB, 0xCC, 0x00}));
  // The ESC's type register 0x0000 as the device's ESC has it.
  const Bytes8 type = run(s, {0x01, 0, 4, 0, 0x00, 0x00, 1, 0});
  EXPECT_EQ(type, (Bytes8{0x81, 0, 1, 0, b.esc().memory()[esc::reg::kType]}));
  // Two requests in one buffer: two replies, in order.
  EXPECT_EQ(run(s, {0x01, 0, 4, 0, 0x00, 0x1F, 1, 0, 0x01, 0, 4, 0, 0x01, 0x1F, 1, 0}),
            (Bytes8{0x81, 0, 1, 0, 0xAA, 0x81, 0, 1, 0, 0xBB}));
}

TEST(PdiSession, TimeAndLinesReplies) {
  Bench b;
  b.p.clock.set(Nanoseconds{1000});
  pdi_host::PdiSession s(b.esc(), pdi_host::PdiChip::Direct, nullptr, b.p.clock);
  EXPECT_EQ(run(s, {0x04, 0, 0, 0}), (Bytes8{0x84, 0, 8, 0, 0xE8, 0x03, 0, 0, 0, 0, 0, 0}));
  // Mask 0x0204 = 1 (AL control event) written by the firmware: LINES shows it.
  (void)run(s, {0x02, 0, 6, 0, 0x04, 0x02, 1, 0, 0, 0});
  EXPECT_EQ(run(s, {0x05, 0, 0, 0}), (Bytes8{0x85, 0, 20, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0,
                                             0xE8, 0x03, 0, 0, 0, 0, 0, 0}));
}

TEST(PdiSession, NotifiesWhenTheAlEventRequestChangesAndOnlyThen) {
  Bench b;
  pdi_host::PdiSession s(b.esc(), pdi_host::PdiChip::Direct, nullptr, b.p.clock);
  Bytes8 out;
  s.greet(out);
  out.clear();
  (void)run(s, {0x02, 0, 6, 0, 0x04, 0x02, 1, 0, 0, 0});  // mask: AL control
  EXPECT_TRUE(s.notify(out, 0));  // the mask changed
  out.clear();
  EXPECT_FALSE(s.notify(out, 0));
  EXPECT_TRUE(out.empty());
  // The master writes AL control (PreOp request): 0x0220 bit 0, the IRQ line
  // high (bit 4 too: the mailbox set-up wrote the SM activation registers).
  ASSERT_TRUE(b.p.master.scan());
  (void)b.p.master.request_state(0, master::AlState::PreOp);  // times out: no firmware answers here
  ASSERT_TRUE(s.notify(out, 0));
  ASSERT_EQ(out.size(), 24u);
  EXPECT_EQ(Bytes8(out.begin(), out.begin() + 14), (Bytes8{0xC1, 0, 20, 0, 0x11, 0, 0, 0, 1, 0, 0, 0, 1, 0}));
  out.clear();
  // The firmware reads AL control: bit 0 clears, the (masked) line drops; one more notification.
  (void)run(s, {0x01, 0, 4, 0, 0x20, 0x01, 2, 0});
  ASSERT_TRUE(s.notify(out, 0));
  EXPECT_EQ(Bytes8(out.begin(), out.begin() + 14), (Bytes8{0xC1, 0, 20, 0, 0x10, 0, 0, 0, 1, 0, 0, 0, 0, 0}));
  out.clear();
  // A SYNC0 pulse is told even when nothing else changed.
  ASSERT_TRUE(s.notify(out, ECAT_PDI_SYNC0));
  EXPECT_EQ(out[13], ECAT_PDI_SYNC0);
}

TEST(PdiSession, MalformedMessagesAreRefusedWithTheirReason) {
  Bench b;
  pdi_host::PdiSession s(b.esc(), pdi_host::PdiChip::Direct, nullptr, b.p.clock);
  auto refused = [&](Bytes8 in) {
    std::string why;
    (void)run(s, std::move(in), &why);
    return why;
  };
  EXPECT_EQ(refused({0x01, 7, 4, 0, 0, 0, 1, 0}), "message type 0x01: reserved header byte is 0x07, not 0");
  EXPECT_EQ(refused({0x33, 0, 0, 0}), "unknown message type 0x33");
  EXPECT_EQ(refused({0x01, 0, 3, 0, 0, 0, 1}), "READ with a 3-byte payload, not 4");
  EXPECT_EQ(refused({0x01, 0, 4, 0, 0xFF, 0xFF, 2, 0}), "READ of 2 bytes at 0xFFFF: outside 0x0000-0xFFFF or empty");
  EXPECT_EQ(refused({0x01, 0, 4, 0, 0x00, 0x10, 0, 0}), "READ of 0 bytes at 0x1000: outside 0x0000-0xFFFF or empty");
  EXPECT_EQ(refused({0x02, 0, 2, 0, 0, 0}), "WRITE without data");
  EXPECT_EQ(refused({0x02, 0, 4, 0, 0xFF, 0xFF, 1, 2}), "WRITE of 2 bytes at 0xFFFF: past 0xFFFF");
  EXPECT_EQ(refused({0x03, 0, 1, 0, 0x03}), "SPI on a direct PDI: send READ and WRITE");
  EXPECT_EQ(refused({0x04, 0, 1, 0, 0}), "TIME with a 1-byte payload, not 0");
  // The replies to the requests before a bad one are kept; the bad one and the rest are not handled.
  Bytes8 in = {0x04, 0, 0, 0, 0x33, 0, 0, 0, 0x04, 0, 0, 0};
  Bytes8 out;
  EXPECT_FALSE(s.handle(in, out, 100));
  EXPECT_EQ(out.size(), 12u);
  // An incomplete message waits for its rest.
  Bytes8 part = {0x01, 0, 4, 0, 0x00};
  out.clear();
  auto r = s.handle(part, out, 100);
  ASSERT_TRUE(r);
  EXPECT_EQ(*r, 0u);
  EXPECT_EQ(part.size(), 5u);
  EXPECT_FALSE(pdi_host::PdiSession::has_message(part));
}

TEST(PdiSession, Lan9252ChipAnswersItsSpiTransactions) {
  Bench b;
  pdi_spi::EmulatedLan9252 chip(b.esc());
  pdi_host::PdiSession s(b.esc(), pdi_host::PdiChip::Lan9252, &chip, b.p.clock);
  // READ of ID_REV 0x0050: instruction, address, 4 data bytes.
  const Bytes8 out = run(s, {0x03, 0, 7, 0, pdi_spi::lan9252::kInstrRead, 0x00, 0x50, 0, 0, 0, 0});
  EXPECT_EQ(out, (Bytes8{0x83, 0, 7, 0, 0, 0, 0, 0x01, 0x00, 0x52, 0x92}));
  std::string why;
  (void)run(s, {0x01, 0, 4, 0, 0, 0, 1, 0}, &why);
  EXPECT_EQ(why, "READ on a lan9252 PDI: send its SPI transactions");
}

}  // namespace
}  // namespace ecat::test
