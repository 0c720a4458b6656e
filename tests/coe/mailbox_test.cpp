#include <gtest/gtest.h>

#include "coe/emergency.hpp"
#include "tests/coe/rig.hpp"

namespace ecat::coe {
namespace {

using test::Frame;
using test::mbx;
using test::sdo;

TEST(MailboxHeader, RoundTrip) {
  const std::uint8_t raw[6] = {0x0A, 0x00, 0x34, 0x12, 0x41, 0x53};
  auto h = MailboxHeader::unpack(raw);
  ASSERT_TRUE(h);
  EXPECT_EQ(h->length, 10);
  EXPECT_EQ(h->address, 0x1234);
  EXPECT_EQ(h->channel, 1);
  EXPECT_EQ(h->priority, 1);
  EXPECT_EQ(h->type, 3);
  EXPECT_EQ(h->counter, 5);
  std::uint8_t out[6]{};
  h->pack(out);
  EXPECT_EQ(Frame(out, out + 6), Frame(raw, raw + 6));
  EXPECT_FALSE(MailboxHeader::unpack(ConstBytes(raw, 5)));
  EXPECT_EQ(MailboxHeader::next_counter(7), 1);
  EXPECT_EQ(MailboxHeader::next_counter(0), 1);
}

TEST(Mailbox, UploadExpeditedByteExact) {
  test::Rig rig;
  auto reply = rig.request(mbx(3, 1, sdo(0x40, 0x1000, 0)));
  ASSERT_TRUE(reply);
  // length 10, address 0, channel 0, CoE with counter 1; SDO response 0x43, 4 bytes.
  EXPECT_EQ(*reply, (Frame{0x0A, 0x00, 0x00, 0x00, 0x00, 0x13, 0x00, 0x30, 0x43, 0x00, 0x10, 0x00, 0x92, 0x01,
                           0x02, 0x00}));
  EXPECT_FALSE(rig.esc.full(0));  // SM0 was released by reading its last byte
}

TEST(Mailbox, ErrorRepliesCarryTheirCodes) {
  test::Rig rig;
  auto expect_error = [&](const Frame& request, std::uint16_t code) {
    auto reply = rig.request(request);
    ASSERT_TRUE(reply);
    ASSERT_EQ(reply->size(), 10u);
    EXPECT_EQ((*reply)[0], 4);
    EXPECT_EQ((*reply)[5] & 0x0F, 0);  // type 0: error reply
    EXPECT_EQ((*reply)[6], 0x01);      // service "error"
    EXPECT_EQ((*reply)[7], 0x00);
    EXPECT_EQ((*reply)[8] | ((*reply)[9] << 8), code);
  };
  expect_error(mbx(2, 1, Frame(10, 0)), 0x0002);             // EoE not offered
  expect_error(mbx(3, 2, sdo(0x40, 0x1000, 0), 5), 0x0003);  // channel 5
  expect_error(mbx(3, 3, {0x00, 0x40}), 0x0004);             // CoE service 4 (TxPDO)
  expect_error(mbx(0, 4, {0x00, 0x00}), 0x0005);             // type 0 from the master
  expect_error(mbx(3, 5, {}), 0x0005);                       // length 0
  expect_error(mbx(3, 6, {0x00}), 0x0006);                   // CoE header cut short
  expect_error(mbx(3, 7, {0x00, 0x20, 0x40, 0x00}), 0x0006);  // SDO header cut short
  Frame too_long = mbx(3, 1, sdo(0x40, 0x1000, 0));
  too_long[0] = 0x7B;  // 123 > 128 - 6
  expect_error(too_long, 0x0008);
  expect_error(mbx(3, 2, {0x00, 0x80, 0x09, 0x00, 0x00, 0x00}), 0x0004);  // SDO info opcode 9
  expect_error(mbx(3, 3, {0x00, 0x80, 0x01, 0x00, 0x00, 0x00}), 0x0006);  // OD list without list type
}

TEST(Mailbox, ClosedOutsidePreOpSafeOpOp) {
  test::Rig rig;
  rig.esc.set_state(0x01);  // Init
  ASSERT_TRUE(rig.esc.master_write(mbx(3, 1, sdo(0x40, 0x1000, 0))));
  rig.mailbox.poll(Nanoseconds{0});
  EXPECT_TRUE(rig.esc.full(0));  // not read
  EXPECT_FALSE(rig.mailbox.open());
  EXPECT_FALSE(rig.mailbox.send(MailboxType::CoE, Frame{1, 2}));
  rig.esc.set_state(0x03);  // Bootstrap: CoE is not offered
  rig.mailbox.poll(Nanoseconds{0});
  auto reply = rig.fetch();
  ASSERT_TRUE(reply);
  EXPECT_EQ((*reply)[8], 0x02);  // unsupported protocol
}

TEST(Mailbox, SameCounterIsARepeatNotANewRequest) {
  test::Rig rig;
  // Download 0x2000 = 7 with counter 3.
  auto first = rig.request(mbx(3, 3, sdo(0x2B, 0x2000, 0, 7)));
  ASSERT_TRUE(first);
  EXPECT_EQ((*first)[8], 0x60);
  // The application changes the value; the same request again (a master
  // that re-sent its write because the frame's WKC got lost) must neither
  // write it a second time nor produce a second reply: SM1 stays empty.
  ASSERT_TRUE(rig.store.set<std::int16_t>(0x2000, 0, 9));
  auto again = rig.request(mbx(3, 3, sdo(0x2B, 0x2000, 0, 7)));
  EXPECT_FALSE(again);
  EXPECT_FALSE(rig.esc.full(1));
  EXPECT_EQ(rig.store.get<std::int16_t>(0x2000, 0), 9);
  // A new counter executes.
  auto third = rig.request(mbx(3, 4, sdo(0x2B, 0x2000, 0, 7)));
  ASSERT_TRUE(third);
  EXPECT_EQ(rig.store.get<std::int16_t>(0x2000, 0), 7);
  EXPECT_NE((*third)[5], (*first)[5]);  // new reply counter
  // Counter 0 (IgH) never counts as a repeat.
  ASSERT_TRUE(rig.store.set<std::int16_t>(0x2000, 0, 1));
  rig.request(mbx(3, 0, sdo(0x2B, 0x2000, 0, 7)));
  ASSERT_TRUE(rig.store.set<std::int16_t>(0x2000, 0, 1));
  rig.request(mbx(3, 0, sdo(0x2B, 0x2000, 0, 7)));
  EXPECT_EQ(rig.store.get<std::int16_t>(0x2000, 0), 7);
}

// SOEM re-sends a mailbox write whose frame came back late (ecx_FPWR with
// EC_TIMEOUTRET3 = 3 x 2 ms); when the firmware had already emptied SM0 the
// ESC takes the copy. A second reply to it would be taken for the answer to
// the next upload by a master that does not empty SM1 before each request
// (SOEM checks only the index, and 1A00h:01..07 share it). Every request gets
// exactly one reply, so the next request is answered by its own reply.
TEST(Mailbox, RepeatedWriteDoesNotShiftTheRepliesOfLaterRequests) {
  test::Rig rig;
  auto first = rig.request(mbx(3, 1, sdo(0x40, 0x1018, 1)));
  ASSERT_TRUE(first);
  EXPECT_FALSE(rig.request(mbx(3, 1, sdo(0x40, 0x1018, 1))));  // the retry
  auto next = rig.request(mbx(3, 2, sdo(0x40, 0x1018, 2)));
  ASSERT_TRUE(next);
  ASSERT_GE(next->size(), 12u);
  EXPECT_EQ((*next)[8], 0x43);   // expedited upload response, 4 bytes
  EXPECT_EQ((*next)[9], 0x18);   // index 1018h ...
  EXPECT_EQ((*next)[10], 0x10);
  EXPECT_EQ((*next)[11], 0x02);  // ... subindex 2, not the repeated 1
  EXPECT_FALSE(rig.fetch());     // nothing left behind
}

TEST(Mailbox, RepeatRequestResendsTheLostReply) {
  test::Rig rig;
  auto lost = rig.request(mbx(3, 1, sdo(0x40, 0x1018, 1)));
  ASSERT_TRUE(lost);  // read by the "ESC", but the frame never reached the master
  rig.esc.master_toggle_repeat();
  EXPECT_FALSE(rig.esc.repeat_acked());
  rig.mailbox.poll(Nanoseconds{0});
  EXPECT_TRUE(rig.esc.repeat_acked());
  auto again = rig.fetch();
  ASSERT_TRUE(again);
  EXPECT_EQ(*again, *lost);
  // Toggle back: works the second time too.
  rig.esc.master_toggle_repeat();
  rig.mailbox.poll(Nanoseconds{0});
  EXPECT_TRUE(rig.esc.repeat_acked());
  EXPECT_EQ(*rig.fetch(), *lost);
}

TEST(Mailbox, RepeatWhileANewerFrameWaitsSendsTheLostOneFirst) {
  test::Rig rig;
  auto a = rig.request(mbx(3, 1, sdo(0x40, 0x1018, 1)));
  ASSERT_TRUE(a);
  // The master's read of a completed but its frame was lost on the way back;
  // meanwhile an emergency went into SM1, with no request in between.
  const Frame emcy{0x00, 0x10, 0x10, 0x32, 0x01, 0, 0, 0, 0, 0};
  ASSERT_TRUE(rig.mailbox.send(MailboxType::CoE, emcy));
  rig.mailbox.poll(Nanoseconds{0});
  ASSERT_TRUE(rig.esc.full(1));
  rig.esc.master_toggle_repeat();
  rig.mailbox.poll(Nanoseconds{0});
  EXPECT_TRUE(rig.esc.repeat_acked());
  EXPECT_EQ(rig.esc.deactivations, 1);
  auto first = rig.fetch();
  ASSERT_TRUE(first);
  EXPECT_EQ(*first, *a);
  auto second = rig.fetch();
  ASSERT_TRUE(second);
  ASSERT_EQ(second->size(), 6 + emcy.size());
  EXPECT_EQ(Frame(second->begin() + 6, second->end()), emcy);
  EXPECT_FALSE(rig.fetch());
}

TEST(Mailbox, RepeatAfterANewRequestKeepsItsUnreadReply) {
  test::Rig rig;
  auto a = rig.request(mbx(3, 1, sdo(0x40, 0x1018, 1)));
  ASSERT_TRUE(a);
  // The master had a, asked for 1018h:02, and its read of SM1 was lost
  // before it reached the ESC (SM1 still full): the repeat is for the reply
  // in SM1, not for a (SOEM's slaveinfo -sdo read every later reply one
  // behind when the older one was put first).
  ASSERT_TRUE(rig.esc.master_write(mbx(3, 2, sdo(0x40, 0x1018, 2))));
  rig.mailbox.poll(Nanoseconds{0});
  ASSERT_TRUE(rig.esc.full(1));
  rig.esc.master_toggle_repeat();
  rig.mailbox.poll(Nanoseconds{0});
  EXPECT_TRUE(rig.esc.repeat_acked());
  EXPECT_EQ(rig.esc.deactivations, 0);  // SM1 left as it was
  auto reply = rig.fetch();
  ASSERT_TRUE(reply);
  EXPECT_EQ((*reply)[11], 2);  // subindex 2
  EXPECT_EQ((*reply)[12], 0x78);
  EXPECT_FALSE(rig.fetch());  // a is not sent again
  // A second loss of the same read, repeated again: still the same reply.
  ASSERT_TRUE(rig.esc.master_write(mbx(3, 3, sdo(0x40, 0x1018, 3))));
  rig.mailbox.poll(Nanoseconds{0});
  rig.esc.master_toggle_repeat();
  rig.mailbox.poll(Nanoseconds{0});
  rig.esc.master_toggle_repeat();
  rig.mailbox.poll(Nanoseconds{0});
  EXPECT_TRUE(rig.esc.repeat_acked());
  auto third = rig.fetch();
  ASSERT_TRUE(third);
  EXPECT_EQ((*third)[11], 3);
  EXPECT_FALSE(rig.fetch());
}

TEST(Mailbox, RepliesQueueWhileSm1IsFullAndAreNeverLost) {
  test::Rig rig(test::make_device(), 4);
  // Five emergencies-worth of replies: the master does not read SM1 for a while.
  ASSERT_TRUE(rig.esc.master_write(mbx(3, 1, sdo(0x40, 0x1018, 1))));
  rig.mailbox.poll(Nanoseconds{0});
  ASSERT_TRUE(rig.esc.master_write(mbx(3, 2, sdo(0x40, 0x1018, 2))));
  rig.mailbox.poll(Nanoseconds{0});
  ASSERT_TRUE(rig.esc.master_write(mbx(3, 3, sdo(0x40, 0x1018, 3))));
  rig.mailbox.poll(Nanoseconds{0});
  ASSERT_TRUE(rig.esc.master_write(mbx(3, 4, sdo(0x40, 0x1018, 4))));
  rig.mailbox.poll(Nanoseconds{0});
  // Queue (capacity 4, one slot reserved) holds replies 2..4; SM1 holds 1.
  ASSERT_TRUE(rig.esc.master_write(mbx(3, 5, sdo(0x40, 0x1000, 0))));
  rig.mailbox.poll(Nanoseconds{0});
  EXPECT_TRUE(rig.esc.full(0));  // not taken: no room for its reply
  EXPECT_FALSE(rig.esc.master_write(mbx(3, 6, sdo(0x40, 0x1000, 0))));  // ESC refuses the write
  for (std::uint8_t sub = 1; sub <= 4; ++sub) {
    auto r = rig.fetch();
    ASSERT_TRUE(r);
    EXPECT_EQ((*r)[11], sub);
  }
  auto last = rig.fetch();
  ASSERT_TRUE(last);
  EXPECT_EQ((*last)[9] | ((*last)[10] << 8), 0x1000);
  EXPECT_FALSE(rig.fetch());
}

// The idle flag a caller keeps (MailboxServer::keep_idle_flag, slave::Firmware)
// is true exactly while has_output() is false, through replies, unsolicited
// messages, a storm and the mailbox closing.
TEST(Mailbox, IdleFlagIsTrueExactlyWhileNothingWaits) {
  test::Rig rig(test::make_device(), 4);
  bool idle = false;
  rig.mailbox.keep_idle_flag(&idle);
  auto check = [&](bool expected, const char* what) {
    EXPECT_EQ(idle, expected) << what;
    EXPECT_EQ(rig.mailbox.has_output(), !expected) << what;
  };
  check(true, "new");
  rig.mailbox.poll(Nanoseconds{0});
  check(true, "open, nothing queued");
  ASSERT_TRUE(rig.mailbox.send(MailboxType::CoE, Frame{0x00, 0x10, 0x11, 0x86}));
  check(false, "emergency queued");
  rig.mailbox.poll(Nanoseconds{0});
  check(true, "emergency in SM1");
  // A request while SM1 is still full: its reply waits in the queue.
  ASSERT_TRUE(rig.esc.master_write(mbx(3, 1, sdo(0x40, 0x1018, 1))));
  rig.mailbox.poll(Nanoseconds{0});
  check(false, "reply queued behind the emergency");
  ASSERT_TRUE(rig.fetch());  // the emergency; the poll inside moves the reply into SM1
  check(true, "reply in SM1");
  ASSERT_TRUE(rig.fetch());
  check(true, "all read");
  // A storm of three: left to send until the last copy is queued and sent.
  ASSERT_TRUE(rig.mailbox.set_unsolicited_storm(MailboxType::CoE, Frame{0x00, 0x10, 0x00, 0x50}, 3));
  check(false, "storm set");
  for (int k = 0; k < 3; ++k) {
    rig.mailbox.poll(Nanoseconds{0});
    ASSERT_TRUE(rig.fetch()) << k;
  }
  check(true, "storm sent");
  // Queued output is dropped when the mailbox closes (Init).
  ASSERT_TRUE(rig.mailbox.send(MailboxType::CoE, Frame{0x00, 0x10, 0x11, 0x86}));
  ASSERT_TRUE(rig.mailbox.send(MailboxType::CoE, Frame{0x00, 0x10, 0x12, 0x86}));
  rig.mailbox.poll(Nanoseconds{0});
  check(false, "one in SM1, one queued");
  rig.esc.set_state(0x01);
  rig.mailbox.poll(Nanoseconds{0});
  check(true, "closed");
  rig.mailbox.keep_idle_flag(nullptr);
  EXPECT_TRUE(idle);  // no longer written
}

}  // namespace
}  // namespace ecat::coe

namespace ecat::coe {
namespace {

using test::Frame;
using test::sdo;

// A request as a mailbox gateway tags it (ETG.8200; KickCAT sets bit 15 and
// an index): Address 0x8003, priority 2.
Frame tagged(std::uint8_t type, std::uint8_t counter, Frame payload, std::uint16_t address, std::uint8_t priority,
             std::uint8_t channel = 0) {
  Frame f = test::mbx(type, counter, std::move(payload), channel);
  f[2] = static_cast<std::uint8_t>(address);
  f[3] = static_cast<std::uint8_t>(address >> 8);
  f[4] = static_cast<std::uint8_t>(f[4] | (priority << 6));
  return f;
}

// Issue 19: replies always carried Address 0, so a gateway never matched them.
TEST(MailboxAddress, EveryReplyEchoesTheRequestsAddressAndPriority) {
  test::Rig rig;
  auto reply = rig.request(tagged(3, 1, sdo(0x40, 0x1000, 0), 0x8003, 2));
  ASSERT_TRUE(reply);
  EXPECT_EQ(*reply, (Frame{0x0A, 0x00, 0x03, 0x80, 0x80, 0x13, 0x00, 0x30, 0x43, 0x00, 0x10, 0x00, 0x92, 0x01,
                           0x02, 0x00}));
  // An SDO abort.
  reply = rig.request(tagged(3, 2, sdo(0x40, 0x5555, 0), 0x0007, 1));
  ASSERT_TRUE(reply);
  EXPECT_EQ(*reply, (Frame{0x0A, 0x00, 0x07, 0x00, 0x40, 0x23, 0x00, 0x20, 0x80, 0x55, 0x55, 0x00, 0x00, 0x00,
                           0x02, 0x06}));
  // Mailbox error replies: unsupported protocol, and a wrong channel (the
  // reply's own channel is 0).
  reply = rig.request(tagged(2, 3, Frame(10, 0), 0x8004, 3));
  ASSERT_TRUE(reply);
  EXPECT_EQ(*reply, (Frame{0x04, 0x00, 0x04, 0x80, 0xC0, 0x30, 0x01, 0x00, 0x02, 0x00}));
  reply = rig.request(tagged(3, 4, sdo(0x40, 0x1000, 0), 0x8005, 0, 5));
  ASSERT_TRUE(reply);
  EXPECT_EQ(*reply, (Frame{0x04, 0x00, 0x05, 0x80, 0x00, 0x40, 0x01, 0x00, 0x03, 0x00}));
  // Length beyond SM0: the header is still read, the error still goes back to it.
  Frame too_long = tagged(3, 5, sdo(0x40, 0x1000, 0), 0x8006, 0);
  too_long[0] = 0x7B;
  reply = rig.request(too_long);
  ASSERT_TRUE(reply);
  EXPECT_EQ(*reply, (Frame{0x04, 0x00, 0x06, 0x80, 0x00, 0x50, 0x01, 0x00, 0x08, 0x00}));
  // A plain master's request (Address 0) is answered with Address 0.
  reply = rig.request(test::mbx(3, 6, sdo(0x40, 0x1000, 0)));
  ASSERT_TRUE(reply);
  EXPECT_EQ(Frame(reply->begin(), reply->begin() + 6), (Frame{0x0A, 0x00, 0x00, 0x00, 0x00, 0x63}));
}

TEST(MailboxAddress, EveryFragmentOfALongAnswerCarriesIt) {
  od::DeviceDescription d = test::make_device();
  for (std::uint16_t i = 0; i < 150; ++i) {
    (void)d.dictionary.put(test::var(static_cast<std::uint16_t>(0x3000 + i), "Filler", od::DataType::Unsigned8, 8, test::kRw));
  }
  test::Rig rig(std::move(d));
  // SDO information, get OD list of all objects: several fragments.
  auto first = rig.request(tagged(3, 1, {0x00, 0x80, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00}, 0x8009, 1));
  ASSERT_TRUE(first);
  EXPECT_EQ(Frame(first->begin() + 2, first->begin() + 5), (Frame{0x09, 0x80, 0x40}));
  int fragments = 1;
  while (auto next = rig.fetch()) {
    EXPECT_EQ(Frame(next->begin() + 2, next->begin() + 5), (Frame{0x09, 0x80, 0x40}));
    ++fragments;
  }
  EXPECT_GT(fragments, 2);
  // Emergencies are the slave's own messages: Address 0, priority 0.
  Emergency emcy(rig.mailbox, rig.store);
  ASSERT_TRUE(emcy.raise(0x8611, 0x81, {1, 2, 3, 4, 5}));
  rig.mailbox.poll(Nanoseconds{0});
  auto msg = rig.fetch();
  ASSERT_TRUE(msg);
  EXPECT_EQ(Frame(msg->begin(), msg->begin() + 5), (Frame{0x0A, 0x00, 0x00, 0x00, 0x00}));
  EXPECT_EQ((*msg)[5] & 0x0F, 0x03);
  EXPECT_EQ(Frame(msg->begin() + 6, msg->begin() + 8), (Frame{0x00, 0x10}));
}

}  // namespace
}  // namespace ecat::coe
