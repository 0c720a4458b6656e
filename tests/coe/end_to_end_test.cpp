// Frame in -> ESC -> mailbox/CoE -> reply out, over the real emulated ESC and
// state machine: what a master on the wire sees.
#include <gtest/gtest.h>

#include "coe/coe_server.hpp"
#include "esc/esc.hpp"
#include "esc/esm.hpp"
#include "esc/registers.hpp"
#include "tests/coe/mini_master.hpp"
#include "tests/coe/rig.hpp"

namespace ecat::coe {
namespace {

using test::Frame;

class EndToEnd : public ::testing::Test {
 protected:
  EndToEnd() : esc_(esc::EscConfig{}, clock_), esm_(esc_, esm_config()), coe_(esc_, device_), master_(segment_, clock_) {
    segment_.add(esc_);
    esm_.add_hooks(coe_.esm_hooks());
    esm_.reset();
    master_.assign_station();
  }
  static esc::EsmConfig esm_config() {
    esc::EsmConfig c;
    c.mailbox_out = {test::kSm0, test::kMbxLen, 0x26};
    c.mailbox_in = {test::kSm1, test::kMbxLen, 0x22};
    c.add_process_sm({esc::kSmOutputs, true, 0x1100, 0x64});
    c.add_process_sm({esc::kSmInputs, false, 0x1180, 0x20});
    return c;
  }
  void cycle() {
    esm_.poll();
    coe_.poll(clock_.now());
  }
  std::uint8_t al_status() { return master_.fprd(esc::reg::kAlStatus, 2).data[0]; }
  std::uint16_t al_code() {
    auto r = master_.fprd(esc::reg::kAlStatusCode, 2);
    return static_cast<std::uint16_t>(r.data[0] | (r.data[1] << 8));
  }
  void request_state(std::uint8_t state) {
    master_.fpwr(esc::reg::kAlControl, {state, 0});
    cycle();
  }
  void to_preop() {
    // SM0 + SM1 in one datagram, as SOEM writes them.
    master_.fpwr(esc::reg::sync_manager(0), {0x00, 0x10, 128, 0, 0x26, 0, 1, 0, 0x80, 0x10, 128, 0, 0x22, 0, 1, 0});
    request_state(0x02);
    ASSERT_EQ(al_status(), 0x02);
  }
  void mailbox_write(const Frame& frame) {
    Frame whole(test::kMbxLen, 0);
    std::copy(frame.begin(), frame.end(), whole.begin());
    ASSERT_EQ(master_.fpwr(test::kSm0, whole), 1);
  }
  std::optional<Frame> mailbox_read() {
    if (!(master_.fprd(0x080D, 1).data[0] & 0x08)) return std::nullopt;
    auto r = master_.fprd(test::kSm1, test::kMbxLen);
    if (r.wkc != 1) return std::nullopt;
    r.data.resize(6 + (r.data[0] | (r.data[1] << 8)));
    return r.data;
  }
  std::optional<Frame> sdo(const Frame& payload) {
    counter_ = MailboxHeader::next_counter(counter_);
    mailbox_write(test::mbx(3, counter_, payload));
    cycle();
    return mailbox_read();
  }

  od::DeviceDescription device_ = test::make_device();
  ManualClock clock_;
  esc::Esc esc_;
  esc::Segment segment_;
  esc::Esm esm_;
  CoeServer coe_;
  test::MiniMaster master_;
  std::uint8_t counter_ = 0;
};

TEST_F(EndToEnd, SdoUploadThroughTheWire) {
  to_preop();
  auto reply = sdo(test::sdo(0x40, 0x1018, 2));
  ASSERT_TRUE(reply);
  EXPECT_EQ(*reply, (Frame{0x0A, 0x00, 0x00, 0x00, 0x00, 0x13, 0x00, 0x30, 0x43, 0x18, 0x10, 0x02, 0x78, 0x56,
                           0x34, 0x12}));
  // Reading SM1 emptied it: a second read gets WKC 0.
  EXPECT_EQ(master_.fprd(test::kSm1, test::kMbxLen).wkc, 0);
}

TEST_F(EndToEnd, TwinCatStyleUsedPartPlusLastByte) {
  to_preop();
  // Write only the used bytes, then the last byte of the SM0 area (shared/spec/masters.md §3.4).
  const Frame req = test::mbx(3, 0, test::sdo(0x40, 0x1018, 4));
  ASSERT_EQ(master_.fpwr(test::kSm0, req), 1);
  cycle();
  EXPECT_FALSE(mailbox_read());  // not complete yet: nothing happened
  ASSERT_EQ(master_.fpwr(test::kSm0 + test::kMbxLen - 1, {0}), 1);
  cycle();
  // Poll the length word (WKC 1 once full), read the used part, then the last byte.
  auto head = master_.fprd(test::kSm1, 2);
  ASSERT_EQ(head.wkc, 1);
  const std::size_t len = 6 + (head.data[0] | (head.data[1] << 8));
  auto body = master_.fprd(test::kSm1, len);
  EXPECT_EQ(body.data, (Frame{0x0A, 0x00, 0x00, 0x00, 0x00, 0x13, 0x00, 0x30, 0x43, 0x18, 0x10, 0x04, 0xFE, 0xCA,
                              0xAD, 0x0B}));
  EXPECT_EQ(master_.fprd(test::kSm1 + test::kMbxLen - 1, 1).wkc, 1);
  EXPECT_EQ(master_.fprd(test::kSm1, 2).wkc, 0);  // empty again
}

TEST_F(EndToEnd, MailboxClosedInInit) {
  master_.fpwr(esc::reg::sync_manager(0), {0x00, 0x10, 128, 0, 0x26, 0, 1, 0, 0x80, 0x10, 128, 0, 0x22, 0, 1, 0});
  cycle();
  // The state machine keeps the mailbox SMs deactivated in Init: the write is refused.
  Frame whole = test::mbx(3, 1, test::sdo(0x40, 0x1000, 0));
  whole.resize(test::kMbxLen);
  EXPECT_EQ(master_.fpwr(test::kSm0, whole), 0);
  cycle();
  EXPECT_FALSE(mailbox_read());
  EXPECT_FALSE(coe_.mailbox().open());
}

TEST_F(EndToEnd, RepeatRequestAfterALostReply) {
  to_preop();
  auto reply = sdo(test::sdo(0x40, 0x1000, 0));
  ASSERT_TRUE(reply);  // ... and imagine this frame was lost on its way back
  auto act = master_.fprd(0x080E, 1).data[0];
  master_.fpwr(0x080E, {static_cast<std::uint8_t>(act ^ 0x02)});
  cycle();
  EXPECT_EQ(master_.fprd(0x080F, 1).data[0] & 0x02, (act ^ 0x02) & 0x02);  // acknowledged
  auto again = mailbox_read();
  ASSERT_TRUE(again);
  EXPECT_EQ(*again, *reply);
}

TEST_F(EndToEnd, PdoRemapThenSafeOpAndCyclicData) {
  to_preop();
  // RxPDO: 1600h = {7001h:00 (8), 7000h:00 (16)}, via complete access from sub 0.
  auto r = sdo(test::sdo(0x31, 0x1600, 0, 10, {2, 0, 0x08, 0x00, 0x01, 0x70, 0x10, 0x00, 0x00, 0x70}));
  ASSERT_TRUE(r);
  EXPECT_EQ((*r)[8], 0x60);
  // SM2 with the wrong length first: refused with 0x001D, stays PreOp with ErrInd.
  master_.fpwr(esc::reg::sync_manager(2), {0x00, 0x11, 2, 0, 0x64, 0, 1, 0, 0x80, 0x11, 5, 0, 0x20, 0, 1, 0});
  request_state(0x04);
  EXPECT_EQ(al_status(), 0x12);
  EXPECT_EQ(al_code(), 0x001D);
  request_state(0x12);  // acknowledge
  master_.fpwr(0x0816, {0});  // SM registers change only while the SM is disabled
  master_.fpwr(esc::reg::sync_manager(2), {0x00, 0x11, 3, 0, 0x64, 0, 1, 0});
  request_state(0x04);
  ASSERT_EQ(al_status(), 0x04) << std::hex << al_code();
  // Mapping is locked outside PreOp.
  r = sdo(test::sdo(0x2F, 0x1600, 0, 0));
  ASSERT_TRUE(r);
  EXPECT_EQ((*r)[8], 0x80);
  EXPECT_EQ((*r)[12] | ((*r)[13] << 8) | ((*r)[14] << 16) | ((*r)[15] << 24), 0x08000022);
  // Outputs in: 7001h first, then 7000h.
  EXPECT_EQ(master_.fpwr(0x1100, {0xAB, 0x34, 0x12}), 1);
  request_state(0x08);
  ASSERT_EQ(al_status(), 0x08);
  coe_.process_data().read_outputs(esc_);
  EXPECT_EQ(coe_.objects().get<std::uint8_t>(0x7001, 0), 0xAB);
  EXPECT_EQ(coe_.objects().get<std::uint16_t>(0x7000, 0), 0x1234);
  // Inputs out.
  ASSERT_TRUE(coe_.objects().set<std::uint32_t>(0x6000, 0, 0x01020304));
  coe_.process_data().write_inputs(esc_);
  auto in = master_.fprd(0x1180, 5);
  EXPECT_EQ(in.wkc, 1);
  EXPECT_EQ(in.data, (Frame{0x04, 0x03, 0x02, 0x01, 0x55}));
}

TEST_F(EndToEnd, EmergencyReachesTheMaster) {
  to_preop();
  ASSERT_TRUE(coe_.emergency().raise(0xFF00, 0x80, {9, 8, 7, 6, 5}));
  cycle();
  auto m = mailbox_read();
  ASSERT_TRUE(m);
  EXPECT_EQ(Frame(m->begin() + 6, m->end()), (Frame{0x00, 0x10, 0x00, 0xFF, 0x80, 9, 8, 7, 6, 5}));
}

}  // namespace
}  // namespace ecat::coe
