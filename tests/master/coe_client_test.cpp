// CoE client against scripted replies: exact request bytes (coe-mailbox.md
// §5.1), expedited/normal/segmented transfers, aborts, counter rotation,
// repeat request, emergencies, SDO information fragments.
#include "master/coe_client.hpp"

#include <gtest/gtest.h>

#include "master_fixture.hpp"

namespace ecat::master::test {
namespace {

using Bytes8 = std::vector<std::uint8_t>;

// A whole mailbox message: header (length, address 0, channel 0, CoE + counter) + payload.
Bytes8 mbx(const Bytes8& payload, std::uint8_t type = 3, std::uint8_t counter = 1) {
  Bytes8 m;
  put16(m, static_cast<std::uint16_t>(payload.size()));
  put16(m, 0);
  m.push_back(0);
  m.push_back(static_cast<std::uint8_t>(type | (counter << 4)));
  m.insert(m.end(), payload.begin(), payload.end());
  return m;
}

class CoeFixture : public MasterFixture {
 protected:
  void SetUp() override {
    scan_and_mailbox();
    fake.on_mailbox = [this](Bytes8 req) {
      requests.push_back(req);
      if (script.empty()) return std::vector<Bytes8>{};
      auto r = script.front();
      script.erase(script.begin());
      return r;
    };
  }
  // Payload (CoE header onward) of request i.
  Bytes8 payload(std::size_t i, std::size_t n) const {
    return Bytes8(requests.at(i).begin() + 6, requests.at(i).begin() + 6 + static_cast<std::ptrdiff_t>(n));
  }
  std::vector<Bytes8> requests;
  std::vector<std::vector<Bytes8>> script;  // replies per request
};

TEST_F(CoeFixture, ExpeditedUploadRequestAndReply) {
  script.push_back({mbx({0x00, 0x30, 0x43, 0x18, 0x10, 0x01, 0x5A, 0x0A, 0x00, 0x00})});
  CoeClient coe(master, 0);
  auto v = coe.upload_value(0x1018, 1);
  ASSERT_TRUE(v.has_value());
  EXPECT_EQ(*v, 0x0A5Au);
  ASSERT_EQ(requests.size(), 1u);
  // Header: length 10, address 0, channel 0, type CoE, counter 1; then 0x2000, 0x40, 0x1018:01.
  EXPECT_EQ(Bytes8(requests[0].begin(), requests[0].begin() + 16),
            (Bytes8{0x0A, 0x00, 0x00, 0x00, 0x00, 0x13, 0x00, 0x20, 0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0}));
  EXPECT_EQ(requests[0].size(), 128u);  // the whole SM0 area is written
}

TEST_F(CoeFixture, ExpeditedDownloadBytesPerSize) {
  for (int i = 0; i < 3; ++i) script.push_back({mbx({0x00, 0x30, 0x60, 0x60, 0x60, 0x00, 0, 0, 0, 0})});
  CoeClient coe(master, 0);
  ASSERT_TRUE(coe.download_value(0x6060, 0, 8, 1).has_value());
  EXPECT_EQ(payload(0, 10), (Bytes8{0x00, 0x20, 0x2F, 0x60, 0x60, 0x00, 0x08, 0, 0, 0}));
  ASSERT_TRUE(coe.download_value(0x6060, 0, 0x1234, 2).has_value());
  EXPECT_EQ(payload(1, 10), (Bytes8{0x00, 0x20, 0x2B, 0x60, 0x60, 0x00, 0x34, 0x12, 0, 0}));
  ASSERT_TRUE(coe.download_value(0x6060, 0, 0xA1B2C3D4, 4).has_value());
  EXPECT_EQ(payload(2, 10), (Bytes8{0x00, 0x20, 0x23, 0x60, 0x60, 0x00, 0xD4, 0xC3, 0xB2, 0xA1}));
  // Counters 1, 2, 3.
  EXPECT_EQ(requests[0][5], 0x13);
  EXPECT_EQ(requests[1][5], 0x23);
  EXPECT_EQ(requests[2][5], 0x33);
}

TEST_F(CoeFixture, CounterWrapsFromSevenToOne) {
  for (int i = 0; i < 8; ++i) script.push_back({mbx({0x00, 0x30, 0x60, 0x00, 0x20, 0x01, 0, 0, 0, 0})});
  CoeClient coe(master, 0);
  for (int i = 0; i < 8; ++i) ASSERT_TRUE(coe.download_value(0x2000, 1, 1, 1).has_value());
  std::vector<int> counters;
  for (auto& r : requests) counters.push_back((r[5] >> 4) & 7);
  EXPECT_EQ(counters, (std::vector<int>{1, 2, 3, 4, 5, 6, 7, 1}));
}

TEST_F(CoeFixture, AbortCodeIsReturnedAsSlaveAbort) {
  script.push_back({mbx({0x00, 0x20, 0x80, 0x00, 0x50, 0x00, 0x00, 0x00, 0x02, 0x06})});
  CoeClient coe(master, 0);
  auto r = coe.upload(0x5000, 0);
  ASSERT_FALSE(r.has_value());
  EXPECT_TRUE(r.error().from_slave);
  EXPECT_EQ(r.error().code, SdoAbortCode::ObjectNotFound);
}

// A reply naming another object (the late answer to an earlier request
// whose wait ran out: 6000h:02 here, and an abort for 6000h:03) is dropped
// and the mailbox read again, as IgH does; the answer to 6000h:01 that
// follows is taken, so later requests are not left one reply behind.
TEST_F(CoeFixture, LateRepliesToOtherObjectsAreDroppedAndTheAnswerTaken) {
  script.push_back({mbx({0x00, 0x30, 0x4F, 0x00, 0x60, 0x02, 0x01, 0, 0, 0}),
                    mbx({0x00, 0x20, 0x80, 0x00, 0x60, 0x03, 0x00, 0x00, 0x02, 0x06}, 3, 2),
                    mbx({0x00, 0x30, 0x4F, 0x00, 0x60, 0x01, 0x2A, 0, 0, 0}, 3, 3)});
  CoeClient coe(master, 0);
  auto r = coe.upload(0x6000, 1);
  ASSERT_TRUE(r.has_value()) << static_cast<int>(r.error().cause);
  EXPECT_EQ(*r, (Bytes8{0x2A}));
  EXPECT_EQ(coe.stale_replies(), 2u);
  EXPECT_EQ(requests.size(), 1u);  // read again, not asked again
}

// Only replies to other objects: no answer comes, the wait runs out.
TEST_F(CoeFixture, OnlyAReplyToAnotherObjectIsATimeout) {
  script.push_back({mbx({0x00, 0x30, 0x4F, 0x00, 0x60, 0x02, 0x01, 0, 0, 0})});
  CoeClient coe(master, 0);
  auto r = coe.upload(0x6000, 1);
  ASSERT_FALSE(r.has_value());
  EXPECT_FALSE(r.error().from_slave);
  EXPECT_EQ(r.error().cause, MasterError::MailboxTimeout);
  EXPECT_EQ(coe.stale_replies(), 1u);
}

TEST_F(CoeFixture, SegmentedUploadReassemblesAndTogglesCompleteAccess) {
  // 20 bytes: 10 in the normal reply, then 7 + 3 in two segments.
  Bytes8 first{0x00, 0x30, 0x51, 0x00, 0x16, 0x00, 20, 0, 0, 0};
  for (std::uint8_t i = 0; i < 10; ++i) first.push_back(i);
  script.push_back({mbx(first)});
  script.push_back({mbx({0x00, 0x30, 0x00, 10, 11, 12, 13, 14, 15, 16})});               // toggle 0, 7 bytes
  script.push_back({mbx({0x00, 0x30, 0x10 | (4 << 1) | 0x01, 17, 18, 19, 0, 0, 0, 0})});  // toggle 1, 3 bytes, last
  CoeClient coe(master, 0);
  auto d = coe.upload(0x1600, 0, true);
  ASSERT_TRUE(d.has_value());
  Bytes8 expected;
  for (std::uint8_t i = 0; i < 20; ++i) expected.push_back(i);
  EXPECT_EQ(*d, expected);
  EXPECT_EQ(payload(0, 10), (Bytes8{0x00, 0x20, 0x50, 0x00, 0x16, 0x00, 0, 0, 0, 0}));  // CA bit
  EXPECT_EQ(payload(1, 3), (Bytes8{0x00, 0x20, 0x60}));
  EXPECT_EQ(payload(2, 3), (Bytes8{0x00, 0x20, 0x70}));
}

TEST_F(CoeFixture, SegmentedDownloadSplitsAtMailboxSize) {
  // 128-byte mailbox: first frame carries 128 - 16 = 112 bytes, segments 119.
  Bytes8 data(300);
  for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<std::uint8_t>(i);
  script.push_back({mbx({0x00, 0x30, 0x60, 0x00, 0x20, 0x00, 0, 0, 0, 0})});
  script.push_back({mbx({0x00, 0x30, 0x20, 0, 0, 0, 0, 0, 0, 0})});
  script.push_back({mbx({0x00, 0x30, 0x30, 0, 0, 0, 0, 0, 0, 0})});
  CoeClient coe(master, 0);
  ASSERT_TRUE(coe.download(0x2000, 0, data).has_value());
  ASSERT_EQ(requests.size(), 3u);
  EXPECT_EQ(load_le<std::uint16_t>(requests[0].data()), 10 + 112);
  EXPECT_EQ(payload(0, 10), (Bytes8{0x00, 0x20, 0x21, 0x00, 0x20, 0x00, 0x2C, 0x01, 0, 0}));
  EXPECT_EQ(requests[0][6 + 10], 0);
  EXPECT_EQ(requests[0][6 + 10 + 111], 111);
  EXPECT_EQ(load_le<std::uint16_t>(requests[1].data()), 3 + 119);
  EXPECT_EQ(requests[1][8], 0x00);  // toggle 0, not last
  EXPECT_EQ(requests[1][9], 112);
  EXPECT_EQ(load_le<std::uint16_t>(requests[2].data()), 3 + 69);
  EXPECT_EQ(requests[2][8], 0x11);  // toggle 1, last
  EXPECT_EQ(requests[2][9], 231);
}

TEST_F(CoeFixture, EmergencyWhileWaitingIsKept) {
  script.push_back({mbx({0x00, 0x10, 0x10, 0x82, 0x11, 1, 2, 3, 4, 5}),
                    mbx({0x00, 0x30, 0x4F, 0x00, 0x10, 0x00, 0x05, 0, 0, 0}, 3, 2)});
  CoeClient coe(master, 0);
  auto v = coe.upload_value(0x1000, 0);
  ASSERT_TRUE(v.has_value());
  EXPECT_EQ(*v, 5u);
  ASSERT_EQ(coe.emergencies().size(), 1u);
  EXPECT_EQ(coe.emergencies()[0].error_code, 0x8210);
  EXPECT_EQ(coe.emergencies()[0].error_register, 0x11);
}

TEST_F(CoeFixture, LostSm1ReadUsesRepeatRequest) {
  script.push_back({mbx({0x00, 0x30, 0x4F, 0x00, 0x10, 0x00, 0x07, 0, 0, 0})});
  fake.lose_next_sm1_read = true;
  CoeClient coe(master, 0);
  auto v = coe.upload_value(0x1000, 0);
  ASSERT_TRUE(v.has_value());
  EXPECT_EQ(*v, 7u);
  // SM1 activate toggled to 0x03 (enable + repeat), PDI control followed.
  auto w = sent(Command::Fpwr, 0x080E);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].data, (Bytes8{0x03}));
}

TEST_F(CoeFixture, MailboxErrorReplyIsReportedWithItsCode) {
  script.push_back({mbx({0x01, 0x00, 0x02, 0x00}, 0)});
  auto c = master.mailbox_send(0, 0x0E, Bytes8{1, 2, 3});
  ASSERT_TRUE(c.has_value());
  auto r = master.mailbox_receive(0, std::chrono::milliseconds(100));
  ASSERT_FALSE(r.has_value());
  EXPECT_EQ(r.error(), MasterError::MailboxErrorReply);
  EXPECT_EQ(master.last_mailbox_error(), mbx::MailboxErrorCode::UnsupportedProtocol);
}

TEST_F(CoeFixture, SdoInfoOdListAcrossFragments) {
  // Fragment 1: incomplete, 1 left, list type 1, 0x1000, 0x1018; fragment 2: 0x6040.
  script.push_back({mbx({0x00, 0x80, 0x82, 0x00, 0x01, 0x00, 0x01, 0x00, 0x00, 0x10, 0x18, 0x10}),
                    mbx({0x00, 0x80, 0x02, 0x00, 0x00, 0x00, 0x40, 0x60}, 3, 2)});
  CoeClient coe(master, 0);
  auto list = coe.od_list();
  ASSERT_TRUE(list.has_value());
  EXPECT_EQ(*list, (std::vector<std::uint16_t>{0x1000, 0x1018, 0x6040}));
  EXPECT_EQ(payload(0, 8), (Bytes8{0x00, 0x80, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00}));
}

TEST_F(CoeFixture, SdoInfoDescriptionsAndInfoError) {
  Bytes8 od{0x00, 0x80, 0x04, 0x00, 0x00, 0x00, 0x18, 0x10, 0x23, 0x00, 0x04, 0x09};
  for (char ch : std::string("Identity")) od.push_back(static_cast<std::uint8_t>(ch));
  script.push_back({mbx(od)});
  Bytes8 oe{0x00, 0x80, 0x06, 0x00, 0x00, 0x00, 0x18, 0x10, 0x01, 0x17, 0x07, 0x00, 0x20, 0x00, 0x07, 0x00};
  for (std::uint8_t b : Bytes8{0x5A, 0x0A, 0x00, 0x00}) oe.push_back(b);  // default value (bit 4)
  for (char ch : std::string("Vendor ID")) oe.push_back(static_cast<std::uint8_t>(ch));
  script.push_back({mbx(oe, 3, 2)});
  script.push_back({mbx({0x00, 0x80, 0x07, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x06}, 3, 3)});
  CoeClient coe(master, 0);
  auto d = coe.object_description(0x1018);
  ASSERT_TRUE(d.has_value());
  EXPECT_EQ(d->data_type, 0x0023);
  EXPECT_EQ(d->max_subindex, 4);
  EXPECT_EQ(d->object_code, 9);
  EXPECT_EQ(d->name, "Identity");
  auto e = coe.entry_description(0x1018, 1, 0x17);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->data_type, 0x0007);
  EXPECT_EQ(e->bit_length, 32);
  EXPECT_EQ(e->access, 0x0007);
  EXPECT_EQ(e->value_data, (Bytes8{0x5A, 0x0A, 0, 0}));
  EXPECT_EQ(e->name, "Vendor ID");
  EXPECT_EQ(payload(1, 10), (Bytes8{0x00, 0x80, 0x05, 0x00, 0x00, 0x00, 0x18, 0x10, 0x01, 0x17}));
  auto missing = coe.object_description(0x5000);
  ASSERT_FALSE(missing.has_value());
  EXPECT_EQ(missing.error().code, SdoAbortCode::ObjectNotFound);
}

TEST_F(CoeFixture, PdoAssignmentTheIghWay) {
  const Bytes8 ok{0x00, 0x30, 0x60, 0x12, 0x1C, 0x00, 0, 0, 0, 0};
  for (int i = 0; i < 4; ++i) {
    Bytes8 r = ok;
    r[5] = static_cast<std::uint8_t>(i == 0 || i == 3 ? 0 : i);
    script.push_back({mbx(r, 3, static_cast<std::uint8_t>(i + 1))});
  }
  CoeClient coe(master, 0);
  const std::uint16_t pdos[]{0x1600, 0x1601};
  ASSERT_TRUE(coe.write_pdo_assignment(0x1C12, pdos).has_value());
  ASSERT_EQ(requests.size(), 4u);
  EXPECT_EQ(payload(0, 10), (Bytes8{0x00, 0x20, 0x2F, 0x12, 0x1C, 0x00, 0x00, 0, 0, 0}));
  EXPECT_EQ(payload(1, 10), (Bytes8{0x00, 0x20, 0x2B, 0x12, 0x1C, 0x01, 0x00, 0x16, 0, 0}));
  EXPECT_EQ(payload(2, 10), (Bytes8{0x00, 0x20, 0x2B, 0x12, 0x1C, 0x02, 0x01, 0x16, 0, 0}));
  EXPECT_EQ(payload(3, 10), (Bytes8{0x00, 0x20, 0x2F, 0x12, 0x1C, 0x00, 0x02, 0, 0, 0}));
}

}  // namespace
}  // namespace ecat::master::test
