// PreOp->SafeOp with process data on more than one SM per direction (issue 14,
// docs/twins.md "Process data on several SMs per direction"): a device without
// mailbox whose outputs are on SM0 (0F00h) and SM1 (0F01h) and inputs on SM2
// (1000h), as Beckhoff's EK1828; each SM is checked on its own (0x001D for an
// outputs SM, 0x001E for an inputs SM, esm-al-codes.md §3), and 1-byte SMs in
// 3-buffer mode hold no buffers (ESC Section II 0x0802), so SMs one byte apart
// do not overlap.
#include <gtest/gtest.h>

#include "esc/esm_sm_check.hpp"
#include "esm_fixture.hpp"

namespace ecat::esc::test {
namespace {

constexpr std::uint16_t kDigitalOut0 = 0x0F00;
constexpr std::uint16_t kDigitalOut1 = 0x0F01;
constexpr std::uint16_t kInputs = 0x1000;
constexpr std::uint8_t kDigitalOutControl = 0x44;  // 3-buffer, ECAT writes, watchdog trigger
constexpr std::uint8_t kInputControl = 0x00;        // 3-buffer, ECAT reads

EsmConfig ek1828_config() {
  EsmConfig c;
  c.has_mailbox = false;
  c.add_process_sm({0, true, kDigitalOut0, kDigitalOutControl});
  c.add_process_sm({1, true, kDigitalOut1, kDigitalOutControl});
  c.add_process_sm({2, false, kInputs, kInputControl});
  return c;
}

class EsmMultiSmTest : public EsmTest {
 protected:
  EsmMultiSmTest() : EsmTest(ek1828_config()) {}
  void preop() {
    request(0x0002);
    ASSERT_EQ(status(), 0x0002);
  }
  void sms(std::uint8_t sm1_control = kDigitalOutControl, std::uint16_t sm2_start = kInputs) {
    pdi.master_sm(0, kDigitalOut0, 1, kDigitalOutControl, true);
    pdi.master_sm(1, kDigitalOut1, 1, sm1_control, true);
    pdi.master_sm(2, sm2_start, 1, kInputControl, true);
  }
};

TEST_F(EsmMultiSmTest, EverySmAsConfiguredReachesSafeOpAndOp) {
  preop();
  sms();
  request(0x0004);
  EXPECT_EQ(status(), 0x0004);
  EXPECT_EQ(code(), 0x0000);
  // SafeOp serves the process-data SMs, SM0/SM1 included (no mailbox here).
  EXPECT_FALSE(deactivated(0));
  EXPECT_FALSE(deactivated(1));
  EXPECT_FALSE(deactivated(2));
  request(0x0008);
  EXPECT_EQ(status(), 0x0008);
}

TEST_F(EsmMultiSmTest, ProcessSmsAreDeactivatedBelowSafeOp) {
  preop();
  EXPECT_TRUE(deactivated(0));
  EXPECT_TRUE(deactivated(1));
  EXPECT_TRUE(deactivated(2));
}

TEST_F(EsmMultiSmTest, SecondOutputsSmWithWrongControlRefusedWith0x001D) {
  preop();
  sms(0x40);  // direction bits say "ECAT reads"
  request(0x0004);
  EXPECT_EQ(status(), 0x0012);
  EXPECT_EQ(code(), 0x001D);
}

TEST_F(EsmMultiSmTest, InputsSmAtAnotherAddressRefusedWith0x001E) {
  preop();
  sms(0x40, 0x1002);  // both wrong: the inputs SM wins, as in SOES
  request(0x0004);
  EXPECT_EQ(status(), 0x0012);
  EXPECT_EQ(code(), 0x001E);
}

TEST_F(EsmMultiSmTest, SecondOutputsSmDisabledWithLengthRefusedWith0x001D) {
  preop();
  sms();
  pdi.master_sm(1, kDigitalOut1, 1, kDigitalOutControl, false);
  request(0x0004);
  EXPECT_EQ(status(), 0x0012);
  EXPECT_EQ(code(), 0x001D);
}

TEST_F(EsmMultiSmTest, SecondOutputsSmDisabledInOpDropsToPreOpWith0x001D) {
  preop();
  sms();
  request(0x0004);
  request(0x0008);
  ASSERT_EQ(status(), 0x0008);
  pdi.master_sm(1, kDigitalOut1, 1, kDigitalOutControl, false);  // raises the SM change event
  esm.poll();
  EXPECT_EQ(status(), 0x0012);
  EXPECT_EQ(code(), 0x001D);
}

// Beckhoff EQ2339: inputs SMs of one byte at 1000h and 1001h, control 00h
// (3-buffer): a 1-byte SM has no buffers, so they do not overlap.
EsmConfig eq2339_inputs() {
  EsmConfig c;
  c.has_mailbox = false;
  c.add_process_sm({2, false, 0x1000, kInputControl});
  c.add_process_sm({3, false, 0x1001, kInputControl});
  return c;
}

class EsmOneByteSmTest : public EsmTest {
 protected:
  EsmOneByteSmTest() : EsmTest(eq2339_inputs()) {}
};

TEST_F(EsmOneByteSmTest, OneByteBufferedSmsOneByteApartDoNotOverlap) {
  request(0x0002);
  pdi.master_sm(2, 0x1000, 1, kInputControl, true);
  pdi.master_sm(3, 0x1001, 1, kInputControl, true);
  request(0x0004);
  EXPECT_EQ(status(), 0x0004);
  EXPECT_EQ(code(), 0x0000);
}

TEST_F(EsmOneByteSmTest, TwoByteBufferedSmsOverlapRefusedWith0x0017) {
  request(0x0002);
  // SM2 2 bytes in 3-buffer mode takes 1000h-1005h; SM3 at 1001h is inside.
  pdi.master_sm(2, 0x1000, 2, kInputControl, true);
  pdi.master_sm(3, 0x1001, 1, kInputControl, true);
  request(0x0004);
  EXPECT_EQ(status(), 0x0012);
  EXPECT_EQ(code(), 0x0017);
}

TEST(SmRegistersTest, FootprintOfOneByteBufferedSmIsOneByte) {
  SmRegisters one{0x1000, 1, 0x00, 0, 1, 0};
  SmRegisters two{0x1000, 2, 0x00, 0, 1, 0};
  SmRegisters mailbox{0x1000, 2, 0x02, 0, 1, 0};
  EXPECT_EQ(one.footprint(), 1u);
  EXPECT_EQ(two.footprint(), 6u);
  EXPECT_EQ(mailbox.footprint(), 2u);
}

}  // namespace
}  // namespace ecat::esc::test
