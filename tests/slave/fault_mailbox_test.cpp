// The mailbox faults of the catalogue beyond the counter and held replies
// (docs/faults.md, issue 26 item 2, as SSC's test application offers them):
// error replies, a reply limit, an emergency storm, a truncated segmented
// upload, a wrong toggle bit - each with the exact mailbox bytes the
// project's master reads while it is engaged, and the slave working again
// once it is cleared.
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "common/le.hpp"
#include "master/coe_client.hpp"
#include "master/mailbox.hpp"
#include "tests/slave/fault_rig.hpp"

namespace ecat::test {
namespace {

using slave::FaultId;
using slave::FaultRequest;

constexpr Nanoseconds kReplyTimeout = std::chrono::milliseconds(100);
constexpr std::uint16_t kDeviceType = 0x1000, kDeviceName = 0x1008, kTxMapping = 0x1A00;

// One generic servo in PreOp with its mailbox set up.
struct MailboxRig : FaultRig {
  MailboxRig() : FaultRig(1) {
    EXPECT_EQ(master.scan().value_or(0), 1u);
    EXPECT_TRUE(master.configure_mailbox(0));
    EXPECT_TRUE(master.request_state(0, master::AlState::PreOp));
  }
  FaultId engage(const std::string& kind, std::map<std::string, std::int64_t> params = {}) {
    return FaultRig::engage(kind, 0, std::move(params));
  }
  // Sends one CoE request and returns the mailbox error code of the reply
  // (the master reads a type-0 reply's service word 0001h and code), -1 for
  // any other reply or none.
  int error_reply(ConstBytes coe_request) {
    if (!master.mailbox_send(0, master::mbx::kTypeCoe, coe_request)) return -1;
    auto m = master.mailbox_receive(0, kReplyTimeout);
    if (m || m.error() != master::MasterError::MailboxErrorReply) return -1;
    return static_cast<int>(master.last_mailbox_error());
  }
  std::pair<std::uint8_t, std::vector<std::uint8_t>> exchange(ConstBytes coe_request) {
    if (!master.mailbox_send(0, master::mbx::kTypeCoe, coe_request)) return {0xFF, {}};
    auto m = master.mailbox_receive(0, kReplyTimeout);
    if (!m) return {0xFF, {}};
    return {m->header.type, std::vector<std::uint8_t>(m->payload.begin(), m->payload.end())};
  }
};

std::vector<std::uint8_t> bytes(std::initializer_list<int> v) {
  std::vector<std::uint8_t> out;
  for (int b : v) out.push_back(static_cast<std::uint8_t>(b));
  return out;
}

// Every request answered with a mailbox error (ETG.1000.4 §5.6: type 0,
// service 0001h, the code) for `count` requests; then SDOs work again.
TEST(FaultMailbox, ErrorRepliesForCountRequests) {
  MailboxRig r;
  r.engage("mailbox_error_replies", {{"code", 4}, {"count", 2}});
  const auto upload = master::CoeClient::upload_request(kDeviceType, 0, false);
  for (int i = 0; i < 2; ++i) EXPECT_EQ(r.error_reply(upload), 0x0004) << i;
  master::CoeClient coe(r.master, 0);
  EXPECT_TRUE(coe.upload_value(kDeviceType, 0));  // spent: the third request is served
  EXPECT_EQ(r.faults.engaged().size(), 1u);       // engaged until cleared (the count only limits the replies)
}

TEST(FaultMailbox, ErrorRepliesUntilClearedWithTheDefaultCode) {
  MailboxRig r;
  const FaultId id = r.engage("mailbox_error_replies");
  const auto upload = master::CoeClient::upload_request(kDeviceType, 0, false);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(r.error_reply(upload), 0x0002) << i;  // unsupported protocol
  master::CoeClient coe(r.master, 0);
  EXPECT_FALSE(coe.upload_value(kDeviceType, 0));
  ASSERT_TRUE(r.faults.clear(id));
  EXPECT_TRUE(coe.upload_value(kDeviceType, 0));
}

// A reply limit of 16 bytes: the device name (13 bytes) no longer fits a
// normal upload reply: 6 bytes come in the initiate reply (CoE 2 + SDO
// header 8 = 10 bytes of header), the other 7 in one upload segment; the
// master reads the same string as without the limit.
TEST(FaultMailbox, ReplyLimitMakesUploadsSegmented) {
  MailboxRig r;
  master::CoeClient coe(r.master, 0);
  const auto whole = coe.upload(kDeviceName, 0);
  ASSERT_TRUE(whole);
  ASSERT_EQ(whole->size(), 13u);  // "Generic servo"
  const FaultId id = r.engage("mailbox_reply_limit", {{"bytes", 16}});
  const auto [type, init] = r.exchange(master::CoeClient::upload_request(kDeviceName, 0, false));
  EXPECT_EQ(type, master::mbx::kTypeCoe);
  ASSERT_EQ(init.size(), 16u);
  EXPECT_EQ(init[2], 0x41);                                  // initiate upload response, size indicated, normal
  EXPECT_EQ(load_le<std::uint32_t>(init.data() + 6), 13u);   // complete size
  EXPECT_EQ(std::string(init.begin() + 10, init.end()), "Generi");
  // The master's own transfer (a new initiate ends the one above): the same bytes.
  EXPECT_EQ(coe.upload(kDeviceName, 0).value_or(std::vector<std::uint8_t>{}), *whole);
  // SDO information in more fragments, the same list.
  ASSERT_TRUE(r.faults.clear(id));
  const auto list = coe.od_list();
  ASSERT_TRUE(list);
  r.engage("mailbox_reply_limit", {{"bytes", 16}});
  const auto limited = coe.od_list();
  ASSERT_TRUE(limited);
  EXPECT_EQ(*limited, *list);
}

// An emergency storm: `count` emergencies, exact bytes, and no more.
TEST(FaultMailbox, EmergencyStormSendsCountEmergencies) {
  MailboxRig r;
  r.engage("emergency_storm", {{"count", 20}, {"code", 0x5530}, {"error_register", 0x81}});
  for (int i = 0; i < 20; ++i) {
    auto m = r.master.mailbox_receive(0, kReplyTimeout);
    ASSERT_TRUE(m) << i;
    EXPECT_EQ(m->header.type, master::mbx::kTypeCoe);
    EXPECT_EQ(std::vector<std::uint8_t>(m->payload.begin(), m->payload.end()),
              bytes({0x00, 0x10, 0x30, 0x55, 0x81, 0, 0, 0, 0, 0}))
        << i;  // CoE service 1 (emergency), 5530h, 1001h byte, 5 manufacturer bytes
  }
  EXPECT_FALSE(r.master.mailbox_receive(0, kReplyTimeout));
  master::CoeClient coe(r.master, 0);
  EXPECT_TRUE(coe.upload_value(kDeviceType, 0));
}

TEST(FaultMailbox, EmergencyStormStopsWhenCleared) {
  MailboxRig r;
  const FaultId id = r.engage("emergency_storm", {{"count", 1000000}});
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(r.master.mailbox_receive(0, kReplyTimeout));
  ASSERT_TRUE(r.faults.clear(id));
  int more = 0;
  while (r.master.mailbox_receive(0, kReplyTimeout)) ++more;
  EXPECT_LE(more, 9);  // what was queued (8) or in SM1 drains, nothing after
  master::CoeClient coe(r.master, 0);
  EXPECT_TRUE(coe.upload_value(kDeviceType, 0));
}

// A segmented upload cut short: with replies of 16 bytes the TxPDO mapping
// 1A00h by complete access is 2 + 4 x entries bytes; its first segment comes
// with the last-segment bit though bytes remain, and the master sees the
// size mismatch.
TEST(FaultMailbox, UploadTruncatedEndsAfterTheFirstSegment) {
  MailboxRig r;
  master::CoeClient coe(r.master, 0);
  const auto whole = coe.upload(kTxMapping, 0, true);
  ASSERT_TRUE(whole);
  ASSERT_GT(whole->size(), 6u + 13u);  // more than the initiate reply and one segment carry
  r.engage("mailbox_reply_limit", {{"bytes", 16}});
  const FaultId id = r.engage("sdo_upload_truncated");
  const auto [t1, init] = r.exchange(master::CoeClient::upload_request(kTxMapping, 0, true));
  ASSERT_EQ(init.size(), 16u);
  EXPECT_EQ(load_le<std::uint32_t>(init.data() + 6), whole->size());
  const auto segment_request = bytes({0x00, 0x20, 0x60, 0, 0, 0, 0, 0, 0, 0});  // upload segment, toggle 0
  const auto [t2, seg] = r.exchange(segment_request);
  ASSERT_EQ(seg.size(), 16u);
  EXPECT_EQ(seg[2], 0x01);  // upload segment response, t = 0, c = 1 (last) with 13 bytes of data
  EXPECT_EQ(std::vector<std::uint8_t>(seg.begin() + 3, seg.end()),
            std::vector<std::uint8_t>(whole->begin() + 6, whole->begin() + 19));
  EXPECT_FALSE(coe.upload(kTxMapping, 0, true));  // the master's own transfer: fewer bytes than announced
  ASSERT_TRUE(r.faults.clear(id));
  EXPECT_EQ(coe.upload(kTxMapping, 0, true).value_or(std::vector<std::uint8_t>{}), *whole);
}

// Wrong toggle: the segment reply carries t = 1 for a request with t = 0.
TEST(FaultMailbox, ToggleWrongInSegmentReplies) {
  MailboxRig r;
  master::CoeClient coe(r.master, 0);
  r.engage("mailbox_reply_limit", {{"bytes", 16}});
  const FaultId id = r.engage("sdo_toggle_wrong");
  (void)r.exchange(master::CoeClient::upload_request(kDeviceName, 0, false));
  const auto [type, seg] = r.exchange(bytes({0x00, 0x20, 0x60, 0, 0, 0, 0, 0, 0, 0}));
  ASSERT_EQ(seg.size(), 10u);
  EXPECT_EQ(seg[2], 0x11);  // upload segment response, t = 1 (wrong), 0 unused, c = 1
  EXPECT_EQ(std::string(seg.begin() + 3, seg.end()), "c servo");
  EXPECT_FALSE(coe.upload(kDeviceName, 0));
  ASSERT_TRUE(r.faults.clear(id));
  EXPECT_TRUE(coe.upload(kDeviceName, 0));
}

TEST(FaultMailbox, RefusesBadParameters) {
  MailboxRig r;
  const std::pair<FaultRequest, std::string> bad[] = {
      {{"mailbox_error_replies", 0, std::nullopt, {{"code", 9}}},
       "mailbox_error_replies: code = 9 is out of range (1..8)"},
      {{"mailbox_reply_limit", 0, std::nullopt, {}}, "mailbox_reply_limit: parameter 'bytes' is required"},
      {{"mailbox_reply_limit", 0, std::nullopt, {{"bytes", 15}}},
       "mailbox_reply_limit: bytes = 15 is out of range (16..65535)"},
      {{"emergency_storm", 0, std::nullopt, {{"count", 0}}}, "emergency_storm: count = 0 is out of range"},
      {{"sdo_toggle_wrong", 0, std::nullopt, {{"count", 1}}}, "sdo_toggle_wrong: unknown parameter 'count'"},
  };
  r.expect_refused(bad);
  r.engage("sdo_toggle_wrong");
  auto twice = r.faults.engage({"sdo_toggle_wrong", 0, std::nullopt, {}});
  ASSERT_FALSE(twice);
  EXPECT_EQ(twice.error(), "sdo_toggle_wrong: already engaged as fault 1");
}

}  // namespace
}  // namespace ecat::test
