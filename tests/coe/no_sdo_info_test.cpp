// A device without SDO information (ESI <CoE> without SdoInfo, SII CoE details
// bit 1 clear) asked for an entry description, as SOEM's slaveinfo -map asks
// whatever the CoE details say. It answers as the Beckhoff SSC answers a CoE
// service it lacks: a mailbox error reply, service 0001h, detail 0004h
// "service not supported" (ETG.1000.4 mailbox error reply; docs/e2e.md "SOEM
// 2.x slaveinfo -map faults on a mailbox error reply"), and on the master's
// repeat request the same bytes again (ESC datasheet Section I §8.2.3).
#include <gtest/gtest.h>

#include "tests/coe/rig.hpp"

namespace ecat::coe {
namespace {

using test::Frame;

struct NoInfoRig {
  NoInfoRig() {
    esc.configure_mailboxes(test::kSm0, test::kMbxLen, test::kSm1, test::kMbxLen);
    mailbox.add_service(coe);
  }
  od::DeviceDescription device = test::make_device();
  test::FakeEsc esc;
  ObjectStore store{device.dictionary};
  SdoServer server{store};
  CoeProtocol coe{server, nullptr};  // no SDO information
  MailboxServer mailbox{esc, test::kMbxLen, MailboxServer::kDefaultQueueCapacity};
};

// The request SOEM 2.x slaveinfo -map sent to the nanotec-c5-e twin (capture
// frame #455): length 10, CoE counter 6, SDO information (service 8), Get
// Entry Description (opcode 5) of 6040h:00 with value info 07h.
const Frame kSoemGetEntryDescription{0x0A, 0x00, 0x00, 0x00, 0x00, 0x63, 0x00, 0x80,
                                     0x05, 0x00, 0x00, 0x00, 0x40, 0x60, 0x00, 0x07};

TEST(NoSdoInformation, EntryDescriptionRequestGetsServiceNotSupportedMailboxError) {
  NoInfoRig rig;
  ASSERT_TRUE(rig.esc.master_write(kSoemGetEntryDescription));
  rig.mailbox.poll(Nanoseconds{0});
  auto reply = rig.esc.master_read();
  ASSERT_TRUE(reply);
  reply->resize(10);
  // Length 4, address 0, channel 0, type 0 (error) with the slave's counter 1;
  // service 0001h, detail 0004h.
  EXPECT_EQ(*reply, (Frame{0x04, 0x00, 0x00, 0x00, 0x00, 0x10, 0x01, 0x00, 0x04, 0x00}));
}

TEST(NoSdoInformation, RepeatRequestResendsTheSameErrorReply) {
  NoInfoRig rig;
  ASSERT_TRUE(rig.esc.master_write(kSoemGetEntryDescription));
  rig.mailbox.poll(Nanoseconds{0});
  auto first = rig.esc.master_read();
  ASSERT_TRUE(first);
  rig.mailbox.poll(Nanoseconds{0});
  EXPECT_FALSE(rig.esc.master_read());  // SM1 empty once read: an ESC gives WKC 0
  rig.esc.master_toggle_repeat();
  rig.mailbox.poll(Nanoseconds{0});
  EXPECT_TRUE(rig.esc.repeat_acked());
  auto again = rig.esc.master_read();
  ASSERT_TRUE(again);
  EXPECT_EQ(*again, *first);
  EXPECT_EQ(Frame(again->begin(), again->begin() + 10),
            (Frame{0x04, 0x00, 0x00, 0x00, 0x00, 0x10, 0x01, 0x00, 0x04, 0x00}));
}

TEST(NoSdoInformation, SdoUploadStillAnsweredAfterTheError) {
  NoInfoRig rig;
  ASSERT_TRUE(rig.esc.master_write(kSoemGetEntryDescription));
  rig.mailbox.poll(Nanoseconds{0});
  ASSERT_TRUE(rig.esc.master_read());
  rig.mailbox.poll(Nanoseconds{0});
  // SDO upload of 1000h:00, counter 7: expedited response, slave counter 2.
  ASSERT_TRUE(rig.esc.master_write(test::mbx(3, 7, test::sdo(0x40, 0x1000, 0))));
  rig.mailbox.poll(Nanoseconds{0});
  auto reply = rig.esc.master_read();
  ASSERT_TRUE(reply);
  EXPECT_EQ((*reply)[5], 0x23);  // CoE, counter 2
  EXPECT_EQ((*reply)[7] >> 4, 3);  // SDO response
  EXPECT_EQ((*reply)[8], 0x43);  // expedited upload, 4 bytes
  EXPECT_EQ((*reply)[9] | ((*reply)[10] << 8), 0x1000);
}

}  // namespace
}  // namespace ecat::coe
