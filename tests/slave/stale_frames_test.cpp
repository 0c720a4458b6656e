// Stale frames are lost on the wire (issue 29 item 4): a frame taken from the
// socket longer than the max frame age after the kernel stamped it is not
// passed, not answered, counted, and changes nothing in the slave; the next
// fresh frame is processed normally. On simulated time, with the exact
// states: the whole ESC memory (SM0/SM1 status, both mailboxes, AL status and
// code), the slave's status and the chain's counters and time.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <vector>

#include "coe/coe_header.hpp"
#include "coe/mailbox_header.hpp"
#include "coe/sdo_command.hpp"
#include "common/frame_builder.hpp"
#include "common/le.hpp"
#include "esc/registers.hpp"
#include "esc/sync_manager.hpp"
#include "slave/frame_age.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

using std::chrono::microseconds;
using std::chrono::milliseconds;
using std::chrono::nanoseconds;

constexpr Nanoseconds kMaxAge = slave::kDefaultMaxFrameAge;
constexpr std::uint16_t kDeviceType = 0x1000;
constexpr std::uint16_t kIdentity = 0x1018;
constexpr std::uint8_t kVendorId = 1;
constexpr std::uint16_t kSm0Status = esc::reg::kSyncManagerBase + esc::reg::sm::kStatus;
constexpr std::uint16_t kSm1Status = esc::reg::kSyncManagerBase + esc::reg::kSyncManagerStride + esc::reg::sm::kStatus;
constexpr std::uint8_t kAlStateInit = static_cast<std::uint8_t>(esc::AlState::Init);
constexpr std::uint8_t kAlStatePreOp = static_cast<std::uint8_t>(esc::AlState::PreOp);

TEST(FrameAge, OlderThanTheLimitIsStaleExactlyAtTheBoundary) {
  const Nanoseconds now = milliseconds(100);
  EXPECT_FALSE(slave::frame_is_stale(now - kMaxAge, now, kMaxAge));  // exactly the limit: kept
  EXPECT_TRUE(slave::frame_is_stale(now - kMaxAge - nanoseconds(1), now, kMaxAge));
  EXPECT_FALSE(slave::frame_is_stale(now, now, kMaxAge));
  EXPECT_FALSE(slave::frame_is_stale(now + milliseconds(5), now, kMaxAge));  // stamped after now (clock step)
  EXPECT_TRUE(slave::frame_is_stale(now - milliseconds(60), now, kMaxAge));
}

TEST(FrameAge, WithoutAStampOrWithTheLimitOffNothingIsStale) {
  const Nanoseconds now = std::chrono::hours(1);
  EXPECT_FALSE(slave::frame_is_stale(std::nullopt, now, kMaxAge));
  EXPECT_FALSE(slave::frame_is_stale(Nanoseconds{0}, now, Nanoseconds{0}));
  EXPECT_FALSE(slave::frame_is_stale(Nanoseconds{0}, now, -kMaxAge));
}

TEST(FrameAge, TheDefaultIsHalfOfSoemsFrameTimeout) {
  // SOEM's EC_TIMEOUTRET: 2000 us per send of a frame (masters.md §1.1); the
  // other half is left for the reply to get back.
  EXPECT_EQ(slave::kDefaultMaxFrameAge, microseconds(2000) / 2);
}

TEST(ChainAdmit, DropsAndCountsOnlyStaleFramesAndLeavesTheTimeAlone) {
  InProcess p;
  p.add_default();
  p.clock.set(milliseconds(10));
  (void)p.chain.poll(p.clock.now());
  // A Chain drops nothing until it is given a limit.
  EXPECT_EQ(p.chain.max_frame_age(), Nanoseconds{0});
  EXPECT_EQ(p.chain.admit(milliseconds(1), milliseconds(10)), milliseconds(10));
  p.chain.set_max_frame_age(kMaxAge);

  const Nanoseconds now = milliseconds(20);
  EXPECT_EQ(p.chain.admit(now - kMaxAge - nanoseconds(1), now), std::nullopt);
  EXPECT_EQ(p.chain.stats().frames_stale, 1u);
  EXPECT_EQ(p.chain.time_seen(), milliseconds(10));  // a lost frame moves no time
  EXPECT_EQ(p.chain.admit(now - kMaxAge, now), now - kMaxAge);
  EXPECT_EQ(p.chain.admit(std::nullopt, now), now);  // no stamp: never stale
  EXPECT_EQ(p.chain.stats().frames_stale, 1u);
  EXPECT_EQ(p.chain.stats().frames_received, 0u);  // admit passes nothing itself
}

// One slave (the embedded generic servo) in PreOp with its mailbox set up
// by the master; frames are then built by hand and taken as run_live takes
// them from the socket.
struct MailboxRig {
  InProcess p;
  master::MailboxLayout mbx;
  std::uint16_t station = 0;
  std::uint8_t next_index = 0x40;

  std::string bring_up() {
    p.add_default();
    auto n = p.master.scan();
    if (!n || *n != 1) return "scan";
    if (!p.master.configure_mailbox(0)) return "mailbox";
    auto st = p.master.request_state(0, master::AlState::PreOp);
    if (!st || st->error()) return "preop";
    mbx = p.master.slave(0).mailbox;
    station = p.master.slave(0).station_address;
    p.chain.set_max_frame_age(kMaxAge);
    return "";
  }

  // FPWR of the whole SM0 area, as SOEM writes it: mailbox header (CoE,
  // counter), CoE header (SDO request), SDO initiate upload of index:sub.
  std::vector<std::uint8_t> upload_request(std::uint16_t index, std::uint8_t sub, std::uint8_t counter) {
    std::vector<std::uint8_t> mailbox(mbx.rx_size, 0);
    coe::MailboxHeader h;
    h.length = static_cast<std::uint16_t>(coe::CoeHeader::kSize + coe::sdo::kHeaderSize);
    h.type = static_cast<std::uint8_t>(coe::MailboxType::CoE);
    h.counter = counter;
    h.pack(Bytes(mailbox));
    ByteWriter w(Bytes(mailbox).subspan(coe::MailboxHeader::kSize));
    coe::CoeHeader::write(w, coe::CoeService::SdoRequest);
    w.u8(coe::sdo::command(coe::sdo::kCcsInitiateUpload));
    w.u16(index);
    w.u8(sub);
    return frame(Command::Fpwr, mbx.rx_start, mailbox);
  }
  // FPRD of the whole SM1 area (a read of the last byte frees it).
  std::vector<std::uint8_t> mailbox_read() {
    return frame(Command::Fprd, mbx.tx_start, std::vector<std::uint8_t>(mbx.tx_size, 0));
  }
  // FPWR of AL control.
  std::vector<std::uint8_t> al_control(std::uint8_t state) {
    return frame(Command::Fpwr, esc::reg::kAlControl, std::vector<std::uint8_t>{state, 0});
  }
  std::vector<std::uint8_t> frame(Command c, std::uint16_t ado, const std::vector<std::uint8_t>& data) {
    std::vector<std::uint8_t> buffer(kMaxEthernetPayload + kEthernetHeaderSize, 0);
    FrameBuilder b(Bytes(buffer), kBroadcastMac, MacAddress{0x01, 0x01, 0x01, 0x01, 0x01, 0x01});
    if (!b.append(c, next_index++, device_address(station, ado), ConstBytes(data))) return {};
    const Bytes f = b.finish();
    return {f.begin(), f.end()};
  }

  // What run_live does with a frame the socket hands it, stamped `arrival`,
  // taken at `now`: admit, then pass it and run the firmware. False: dropped.
  bool take(std::vector<std::uint8_t>& f, std::optional<Nanoseconds> arrival, Nanoseconds now) {
    const std::optional<Nanoseconds> at = p.chain.admit(arrival, now);
    if (!at) return false;
    const bool back = p.chain.pass_frame(f, *at);
    p.chain.run_firmware(*at);
    return back;
  }

  // The WKC and data of the one datagram of a frame built by frame().
  static std::uint16_t wkc(const std::vector<std::uint8_t>& f, std::size_t data_size) {
    return load_le<std::uint16_t>(f.data() + kEthernetHeaderSize + kFrameHeaderSize + kDatagramHeaderSize + data_size);
  }
  static std::span<const std::uint8_t> data(const std::vector<std::uint8_t>& f, std::size_t size) {
    return std::span<const std::uint8_t>(f).subspan(kEthernetHeaderSize + kFrameHeaderSize + kDatagramHeaderSize,
                                                    size);
  }
  std::vector<std::uint8_t> memory() {
    const esc::Esc& e = p.chain[0].esc();
    return {e.memory(), e.memory() + e.memory_size()};
  }
  std::uint8_t reg8(std::uint16_t address) { return p.chain[0].esc().memory()[address]; }

  // The SDO upload reply in a read SM1 area: index, subindex and command.
  struct Reply {
    std::uint8_t service = 0;
    std::uint8_t command = 0;
    std::uint16_t index = 0;
    std::uint8_t sub = 0;
    std::uint32_t value = 0;
  };
  static Reply reply(std::span<const std::uint8_t> mailbox) {
    const std::uint8_t* d = mailbox.data() + coe::MailboxHeader::kSize;
    const coe::CoeHeader ch = coe::CoeHeader::unpack(load_le<std::uint16_t>(d));
    d += coe::CoeHeader::kSize;
    return {ch.service, d[0], load_le<std::uint16_t>(d + 1), d[3], load_le<std::uint32_t>(d + 4)};
  }
};

constexpr std::uint8_t kExpeditedUploadReply =
    coe::sdo::command(coe::sdo::kScsInitiateUpload, coe::sdo::kExpedited | coe::sdo::kSizeIndicated);

TEST(StaleFrames, AStaleMailboxWriteChangesNothingAndTheNextFreshOneIsAnswered) {
  MailboxRig rig;
  ASSERT_EQ(rig.bring_up(), "");
  rig.p.advance(milliseconds(10));
  const Nanoseconds now = rig.p.clock.now();
  const std::vector<std::uint8_t> before = rig.memory();
  const slave::SlaveStatus status = rig.p.chain[0].status();
  const slave::ChainStats stats = rig.p.chain.stats();
  const Nanoseconds seen = rig.p.chain.time_seen();
  ASSERT_EQ(rig.reg8(kSm0Status) & esc::sm_bits::kStatusMailboxFull, 0);
  ASSERT_EQ(rig.reg8(kSm1Status) & esc::sm_bits::kStatusMailboxFull, 0);
  ASSERT_EQ(rig.reg8(esc::reg::kAlStatus), kAlStatePreOp);

  // Taken 1 ns past the limit: lost. The frame is not answered (its WKC
  // stays 0) and not one byte of the ESC changes: SM0 status, SM0 and SM1
  // areas, AL status and code, the event registers.
  std::vector<std::uint8_t> stale = rig.upload_request(kDeviceType, 0, 1);
  const std::vector<std::uint8_t> sent = stale;
  EXPECT_FALSE(rig.take(stale, now - kMaxAge - nanoseconds(1), now));
  EXPECT_EQ(stale, sent);
  EXPECT_EQ(rig.memory(), before);
  EXPECT_EQ(rig.p.chain[0].status().state, status.state);
  EXPECT_EQ(rig.p.chain[0].status().code, status.code);
  EXPECT_EQ(rig.p.chain[0].status().firmware_polls, status.firmware_polls);
  EXPECT_EQ(rig.p.chain.stats().frames_stale, stats.frames_stale + 1);
  EXPECT_EQ(rig.p.chain.stats().frames_received, stats.frames_received);
  EXPECT_EQ(rig.p.chain.stats().frames_returned, stats.frames_returned);
  EXPECT_EQ(rig.p.chain.time_seen(), seen);

  // The master's next send of the same request, exactly at the limit: the
  // ESC takes it (WKC 1), the firmware answers it in SM1.
  std::vector<std::uint8_t> fresh = rig.upload_request(kDeviceType, 0, 1);
  EXPECT_TRUE(rig.take(fresh, now - kMaxAge, now));
  EXPECT_EQ(MailboxRig::wkc(fresh, rig.mbx.rx_size), 1);
  EXPECT_EQ(rig.reg8(kSm0Status) & esc::sm_bits::kStatusMailboxFull, 0);  // the firmware read it
  EXPECT_EQ(rig.reg8(kSm1Status) & esc::sm_bits::kStatusMailboxFull, esc::sm_bits::kStatusMailboxFull);
  std::vector<std::uint8_t> read = rig.mailbox_read();
  EXPECT_TRUE(rig.take(read, now, now));
  EXPECT_EQ(MailboxRig::wkc(read, rig.mbx.tx_size), 1);
  const MailboxRig::Reply r = MailboxRig::reply(MailboxRig::data(read, rig.mbx.tx_size));
  EXPECT_EQ(r.service, static_cast<std::uint8_t>(coe::CoeService::SdoResponse));
  EXPECT_EQ(r.command, kExpeditedUploadReply);
  EXPECT_EQ(r.index, kDeviceType);
  EXPECT_EQ(r.sub, 0);
  EXPECT_EQ(rig.p.chain.stats().frames_stale, stats.frames_stale + 1);
  EXPECT_EQ(rig.p.chain.stats().frames_received, stats.frames_received + 2);
}

// The queue SOEM 2.x left behind on a loaded host (issue 29): the process
// stalled 60 ms while SOEM sent request 1 three times (2 ms apart) and gave
// up, then sent request 2 (a retry of each every 2 ms would not change it:
// they would be stale too). With the limit, the three copies are lost and the
// reply read is request 2's; without it, the slave takes request 1 behind the
// master's back and the reply read answers request 1 - the master's way lost.
struct SoemQueueOutcome {
  std::uint16_t replied_index = 0;
  std::uint8_t replied_sub = 0;
  std::uint16_t request2_wkc = 0;
  std::uint64_t stale = 0;
};

SoemQueueOutcome soem_queue(Nanoseconds max_age) {
  MailboxRig rig;
  EXPECT_EQ(rig.bring_up(), "");
  rig.p.chain.set_max_frame_age(max_age);
  rig.p.advance(milliseconds(10));
  const Nanoseconds t0 = rig.p.clock.now();
  const Nanoseconds woke = t0 + milliseconds(60) + microseconds(100);
  rig.p.clock.set(woke);
  SoemQueueOutcome out;
  for (int copy = 0; copy < 3; ++copy) {
    std::vector<std::uint8_t> f = rig.upload_request(kDeviceType, 0, 1);
    (void)rig.take(f, t0 + copy * milliseconds(2), woke);
  }
  std::vector<std::uint8_t> second = rig.upload_request(kIdentity, kVendorId, 2);
  (void)rig.take(second, t0 + milliseconds(60), woke);
  out.request2_wkc = MailboxRig::wkc(second, rig.mbx.rx_size);
  std::vector<std::uint8_t> read = rig.mailbox_read();
  (void)rig.take(read, woke, woke);
  const MailboxRig::Reply r = MailboxRig::reply(MailboxRig::data(read, rig.mbx.tx_size));
  out.replied_index = r.index;
  out.replied_sub = r.sub;
  out.stale = rig.p.chain.stats().frames_stale;
  return out;
}

TEST(StaleFrames, RetriedRequestsAMasterGaveUpOnAreLostAndTheReplyAnswersTheNextRequest) {
  const SoemQueueOutcome o = soem_queue(kMaxAge);
  EXPECT_EQ(o.stale, 3u);
  EXPECT_EQ(o.request2_wkc, 1);
  EXPECT_EQ(o.replied_index, kIdentity);
  EXPECT_EQ(o.replied_sub, kVendorId);
}

TEST(StaleFrames, WithoutTheLimitTheSameQueueAnswersTheRequestTheMasterGaveUpOn) {
  const SoemQueueOutcome o = soem_queue(Nanoseconds{0});
  EXPECT_EQ(o.stale, 0u);
  EXPECT_EQ(o.replied_index, kDeviceType);  // the reply of request 1, read as request 2's
}

TEST(StaleFrames, AStaleAlControlWriteLeavesTheAlStatus) {
  MailboxRig rig;
  ASSERT_EQ(rig.bring_up(), "");
  rig.p.advance(milliseconds(10));
  const Nanoseconds now = rig.p.clock.now();
  const std::vector<std::uint8_t> before = rig.memory();
  std::vector<std::uint8_t> stale = rig.al_control(kAlStateInit);
  EXPECT_FALSE(rig.take(stale, now - milliseconds(60), now));
  EXPECT_EQ(rig.memory(), before);
  EXPECT_EQ(rig.reg8(esc::reg::kAlStatus), kAlStatePreOp);
  EXPECT_EQ(rig.p.chain[0].status().state, esc::AlState::PreOp);

  std::vector<std::uint8_t> fresh = rig.al_control(kAlStateInit);
  EXPECT_TRUE(rig.take(fresh, now - microseconds(100), now));
  EXPECT_EQ(MailboxRig::wkc(fresh, 2), 1);
  EXPECT_EQ(rig.reg8(esc::reg::kAlStatus), kAlStateInit);
  EXPECT_EQ(rig.p.chain[0].status().state, esc::AlState::Init);
  EXPECT_EQ(rig.p.chain.stats().frames_stale, 1u);
}

}  // namespace
}  // namespace ecat::test
