#include "coe/emergency.hpp"

#include <gtest/gtest.h>

#include "tests/coe/rig.hpp"

namespace ecat::coe {
namespace {

using test::Frame;

TEST(Emergency, QueuedAsCoEServiceOneAndSetsErrorRegister) {
  test::Rig rig;
  Emergency emcy(rig.mailbox, rig.store);
  rig.mailbox.poll(Nanoseconds{0});  // open the mailbox
  ASSERT_TRUE(emcy.raise(0x8611, 0x81, {1, 2, 3, 4, 5}));
  rig.mailbox.poll(Nanoseconds{0});
  auto msg = rig.fetch();
  ASSERT_TRUE(msg);
  EXPECT_EQ(*msg, (Frame{0x0A, 0x00, 0x00, 0x00, 0x00, 0x13, 0x00, 0x10, 0x11, 0x86, 0x81, 1, 2, 3, 4, 5}));
  EXPECT_EQ(rig.store.get<std::uint8_t>(0x1001, 0), 0x81);
}

TEST(Emergency, ClosedMailboxStillUpdatesTheRegister) {
  test::Rig rig;
  rig.esc.set_state(0x01);
  Emergency emcy(rig.mailbox, rig.store);
  rig.mailbox.poll(Nanoseconds{0});
  EXPECT_EQ(emcy.raise(0x5000, 0x01).error(), MailboxError::NoMoreMemory);
  EXPECT_EQ(rig.store.get<std::uint8_t>(0x1001, 0), 0x01);
}

TEST(Emergency, UnsolicitedMessagesLongerThanAnEmergencyAreRefused) {
  // The unsolicited queue's slots hold an emergency (mailbox header + 10
  // bytes, issue 16 item 5): a longer message is refused, not cut.
  test::Rig rig;
  rig.mailbox.poll(Nanoseconds{0});
  const Frame longest(MailboxServer::kMaxUnsolicitedPayload, 0x5A);
  const Frame longer(MailboxServer::kMaxUnsolicitedPayload + 1, 0x5A);
  EXPECT_EQ(rig.mailbox.send(MailboxType::CoE, longer).error(), MailboxError::InvalidSize);
  ASSERT_TRUE(rig.mailbox.send(MailboxType::CoE, longest));
  rig.mailbox.poll(Nanoseconds{0});
  auto msg = rig.fetch();
  ASSERT_TRUE(msg);
  ASSERT_EQ(msg->size(), 6 + longest.size());
  EXPECT_EQ(Frame(msg->begin() + 6, msg->end()), longest);
  EXPECT_EQ((*msg)[0], longest.size());
}

TEST(Emergency, FullQueueIsReportedNotOverwritten) {
  test::Rig rig(test::make_device(), 3);
  Emergency emcy(rig.mailbox, rig.store);
  rig.mailbox.poll(Nanoseconds{0});
  ASSERT_TRUE(emcy.raise(0x1000, 1));
  ASSERT_TRUE(emcy.raise(0x1001, 1));
  ASSERT_TRUE(emcy.raise(0x1002, 1));
  // SM1 is written at the next poll: the queue holds three; a fourth does not fit.
  EXPECT_EQ(emcy.raise(0x1003, 1).error(), MailboxError::NoMoreMemory);
  rig.mailbox.poll(Nanoseconds{0});
  EXPECT_EQ((*rig.fetch())[8], 0x00);
  EXPECT_EQ((*rig.fetch())[8], 0x01);
  EXPECT_EQ((*rig.fetch())[8], 0x02);
  EXPECT_FALSE(rig.fetch());
}

// shared/spec/masters.md §6 #26: a master waiting for an SDO reply must not
// find an emergency in its place.
TEST(Emergency, NeverInPlaceOfAPendingReply) {
  test::Rig rig;
  Emergency emcy(rig.mailbox, rig.store);
  rig.mailbox.poll(Nanoseconds{0});
  // A request is waiting in SM0 when the emergency is raised: the reply goes first.
  ASSERT_TRUE(rig.esc.master_write(test::mbx(3, 1, test::sdo(0x40, 0x1000, 0))));
  ASSERT_TRUE(emcy.raise(0x5000, 1));
  rig.mailbox.poll(Nanoseconds{0});
  auto first = rig.fetch();
  ASSERT_TRUE(first);
  EXPECT_EQ((*first)[7], 0x30);  // SDO response
  auto second = rig.fetch();
  ASSERT_TRUE(second);
  EXPECT_EQ((*second)[7], 0x10);  // then the emergency
  // During a segmented upload it waits for the last segment.
  ASSERT_TRUE(rig.store.assign(0x2002, 0, Frame(300, 0x11)));
  auto init = rig.request(test::mbx(3, 2, test::sdo(0x40, 0x2002, 0)));
  ASSERT_TRUE(init);
  ASSERT_TRUE(emcy.raise(0x5001, 1));
  bool toggle = false;
  std::uint8_t counter = 3;
  for (;;) {
    auto seg = rig.request(test::mbx(3, counter, test::sdo(toggle ? 0x70 : 0x60, 0, 0)));
    counter = MailboxHeader::next_counter(counter);
    ASSERT_TRUE(seg);
    ASSERT_EQ((*seg)[7], 0x30) << "an emergency came in place of a segment";
    if ((*seg)[8] & 0x01) break;
    toggle = !toggle;
  }
  auto after = rig.fetch();
  ASSERT_TRUE(after);
  EXPECT_EQ((*after)[7], 0x10);
}

TEST(Emergency, DiagnosisHistory) {
  od::DeviceDescription d = test::make_device();
  od::Object diag = test::composite(0x10F3, "Diagnosis History", od::ObjectCode::Record, od::DataType::Record, test::kRo,
                                    {test::entry(1, "Maximum Messages", od::DataType::Unsigned8, 8, test::kRo, {2}),
                                     test::entry(2, "Newest Message", od::DataType::Unsigned8, 8, test::kRo, {0}),
                                     test::entry(3, "Newest Acknowledged Message", od::DataType::Unsigned8, 8, test::kRw, {0}),
                                     test::entry(4, "New Messages Available", od::DataType::Boolean, 1, test::kRo, {0}),
                                     test::entry(5, "Flags", od::DataType::Unsigned16, 16, test::kRw),
                                     test::entry(6, "Diagnosis Message 001", od::DataType::OctetString, 8 * 28, test::kRo),
                                     test::entry(7, "Diagnosis Message 002", od::DataType::OctetString, 8 * 28, test::kRo)});
  (void)d.dictionary.put(diag);
  test::Rig rig(std::move(d));
  DiagnosisHistory history(rig.store);
  ASSERT_TRUE(history.present());
  Emergency emcy(rig.mailbox, rig.store, &history);
  (void)emcy.raise(0x2310, 0x03, {}, Nanoseconds{0x0102030405});
  EXPECT_EQ(rig.store.get<std::uint8_t>(0x10F3, 2), 6);
  EXPECT_EQ(rig.store.get<std::uint8_t>(0x10F3, 4), 1);
  const auto m = rig.store.value(0x10F3, 6);
  // Diag Code E800h | 2310h << 16, error with a local time stamp (flags bit
  // 4), no parameters, text ID 0, time stamp.
  EXPECT_EQ(Frame(m.begin(), m.end()),
            (Frame{0x00, 0xE8, 0x10, 0x23, 0x12, 0x00, 0, 0, 0x05, 0x04, 0x03, 0x02, 0x01, 0, 0, 0}));
  (void)emcy.raise(0x2311, 0x03);
  EXPECT_EQ(rig.store.get<std::uint8_t>(0x10F3, 2), 7);
  (void)emcy.raise(0x2312, 0x03);
  EXPECT_EQ(rig.store.get<std::uint8_t>(0x10F3, 2), 6);  // ring of two
  EXPECT_EQ(rig.store.value(0x10F3, 6)[2], 0x12);
  Emergency without(rig.mailbox, rig.store);  // no history given: 10F3h untouched
  (void)without.raise(0x2313, 0x03);
  EXPECT_EQ(rig.store.value(0x10F3, 6)[2], 0x12);
}

}  // namespace
}  // namespace ecat::coe
