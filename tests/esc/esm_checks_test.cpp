// What the ESM checks before going up (esm-al-codes.md §3): mailbox SMs at
// Init->PreOp (0x0016) and Init->Boot (0x0013/0x0015), SM2/SM3 at
// PreOp->SafeOp (0x001D/0x001E/0x0017), outputs before Op (0x001B), hooks.
#include <gtest/gtest.h>

#include "esm_fixture.hpp"

namespace ecat::esc::test {
namespace {

struct SmSetting {
  const char* name;
  unsigned sm;
  std::uint16_t start, length;
  std::uint8_t control;
  bool enable;
};

class EsmMailboxCheckTest : public EsmTest, public ::testing::WithParamInterface<SmSetting> {};

TEST_P(EsmMailboxCheckTest, WrongMailboxRefusedWith0x0016) {
  const SmSetting s = GetParam();
  mailbox_sms();
  pdi.master_sm(s.sm, s.start, s.length, s.control, s.enable);
  request(0x0002);
  EXPECT_EQ(status(), 0x0011);
  EXPECT_EQ(code(), 0x0016);
  EXPECT_TRUE(deactivated(0));
  EXPECT_TRUE(deactivated(1));
  EXPECT_TRUE(hooks.checks.empty());  // own checks come before the hooks
}

INSTANTIATE_TEST_SUITE_P(
    Settings, EsmMailboxCheckTest,
    ::testing::Values(SmSetting{"sm0_start", 0, 0x1001, kMbxLength, kMbxOutControl, true},
                      SmSetting{"sm0_length", 0, kMbxOutStart, 64, kMbxOutControl, true},
                      SmSetting{"sm0_control", 0, kMbxOutStart, kMbxLength, 0x22, true},
                      SmSetting{"sm0_disabled", 0, kMbxOutStart, kMbxLength, kMbxOutControl, false},
                      SmSetting{"sm1_start", 1, 0x1100, kMbxLength, kMbxInControl, true},
                      SmSetting{"sm1_length", 1, kMbxInStart, 256, kMbxInControl, true},
                      SmSetting{"sm1_control", 1, kMbxInStart, kMbxLength, 0x26, true},
                      SmSetting{"sm1_disabled", 1, kMbxInStart, kMbxLength, kMbxInControl, false}),
    [](const auto& p) { return std::string(p.param.name); });

TEST_F(EsmTest, BootstrapNotSupported) {
  request(0x0003);
  EXPECT_EQ(status(), 0x0011);
  EXPECT_EQ(code(), 0x0013);
}

class EsmBootTest : public EsmTest {
 protected:
  static EsmConfig boot_config() {
    EsmConfig c = test_esm_config();
    c.bootstrap_supported = true;
    return c;
  }
  EsmBootTest() : EsmTest(boot_config()) {}
};

TEST_F(EsmBootTest, StandardMailboxIsNotTheBootMailbox) {
  mailbox_sms();
  request(0x0003);
  EXPECT_EQ(status(), 0x0011);
  EXPECT_EQ(code(), 0x0015);
}

TEST_F(EsmBootTest, BootWithBootMailboxThenBackToInit) {
  pdi.master_sm(0, kBootOutStart, kBootLength, kMbxOutControl, true);
  pdi.master_sm(1, kBootInStart, kBootLength, kMbxInControl, true);
  request(0x0003);
  EXPECT_EQ(status(), 0x0003);
  EXPECT_EQ(code(), 0x0000);
  EXPECT_FALSE(deactivated(0));
  request(0x0002);  // Boot -> PreOp is not allowed
  EXPECT_EQ(status(), 0x0013);
  EXPECT_EQ(code(), 0x0011);
  request(0x0011);
  EXPECT_EQ(status(), 0x0001);
  EXPECT_EQ(code(), 0x0000);
  EXPECT_TRUE(deactivated(0));
}

TEST_F(EsmBootTest, BootMailboxChangedInBootFallsToInit) {
  pdi.master_sm(0, kBootOutStart, kBootLength, kMbxOutControl, true);
  pdi.master_sm(1, kBootInStart, kBootLength, kMbxInControl, true);
  request(0x0003);
  pdi.master_sm(1, kBootInStart, kBootLength, kMbxInControl, false);
  esm.poll();
  EXPECT_EQ(status(), 0x0011);
  EXPECT_EQ(code(), 0x0015);
}

struct ProcessCase {
  const char* name;
  unsigned sm;
  std::uint16_t start, length;
  std::uint8_t control;
  bool enable;
  std::uint16_t code;
};

class EsmProcessCheckTest : public EsmTest, public ::testing::WithParamInterface<ProcessCase> {};

TEST_P(EsmProcessCheckTest, PreOpToSafeOpRefused) {
  const ProcessCase c = GetParam();
  go_preop();
  process_sms();
  pdi.master_sm(c.sm, c.start, c.length, c.control, c.enable);
  request(0x0004);
  EXPECT_EQ(status(), 0x0012);
  EXPECT_EQ(code(), c.code);
  EXPECT_TRUE(deactivated(2));
  EXPECT_TRUE(deactivated(3));
}

INSTANTIATE_TEST_SUITE_P(
    Settings, EsmProcessCheckTest,
    ::testing::Values(ProcessCase{"sm2_start", 2, 0x1104, 4, kOutControl, true, 0x001D},
                      ProcessCase{"sm2_control", 2, kOutStart, 4, 0x24, true, 0x001D},
                      ProcessCase{"sm2_length_but_disabled", 2, kOutStart, 4, kOutControl, false, 0x001D},
                      ProcessCase{"sm2_enabled_without_length", 2, kOutStart, 0, kOutControl, true, 0x001D},
                      ProcessCase{"sm3_start", 3, 0x1000, 6, kInControl, true, 0x001E},
                      ProcessCase{"sm3_control", 3, kInStart, 6, 0x00, true, 0x001E},
                      ProcessCase{"sm3_disabled", 3, kInStart, 6, kInControl, false, 0x001E},
                      // 3 buffers of 0x30 bytes from 0x1100 reach into SM3 at 0x1180.
                      ProcessCase{"sm2_three_buffers_overlap_sm3", 2, kOutStart, 0x30, kOutControl, true,
                                  0x0017}),
    [](const auto& p) { return std::string(p.param.name); });

TEST_F(EsmTest, InputsWinWhenBothProcessSmsAreWrong) {
  go_preop();
  pdi.master_sm(2, 0x1200, 4, kOutControl, true);
  pdi.master_sm(3, 0x1300, 4, kInControl, true);
  request(0x0004);
  EXPECT_EQ(code(), 0x001E);
}

TEST_F(EsmTest, DeviceWithoutOutputsLeavesSm2Disabled) {
  go_preop();
  process_sms(0, 6);
  request(0x0004);
  EXPECT_EQ(status(), 0x0004);
}

TEST_F(EsmTest, HookRefusalGivesItsCodeAndCurrentState) {
  go_preop();
  process_sms();
  hooks.refuse_to = AlState::SafeOp;
  hooks.refusal = AlStatusCode::InvalidOutputMapping;
  request(0x0004);
  EXPECT_EQ(status(), 0x0012);
  EXPECT_EQ(code(), 0x0025);
  ASSERT_FALSE(hooks.checks.empty());
  EXPECT_EQ(hooks.checks.back().from, AlState::PreOp);
  EXPECT_EQ(hooks.checks.back().to, AlState::SafeOp);
}

TEST_F(EsmTest, FirstRefusingHookWinsAndLaterHooksAreNotAsked) {
  RecordingHooks second;
  second.refuse_to = AlState::SafeOp;
  second.refusal = AlStatusCode::FreeRunNotSupported;
  ASSERT_TRUE(esm.add_hooks(second));
  hooks.refuse_to = AlState::SafeOp;
  hooks.refusal = AlStatusCode::InvalidInputMapping;
  go_preop();
  process_sms();
  request(0x0004);
  EXPECT_EQ(code(), 0x0024);
  EXPECT_TRUE(second.checks.empty() || second.checks.back().to != AlState::SafeOp);
}

TEST_F(EsmTest, HookCapacityIsFixed) {
  std::array<RecordingHooks, Esm::kMaxHooks> more;
  std::size_t accepted = 0;
  for (auto& h : more) accepted += esm.add_hooks(h) ? 1u : 0u;
  EXPECT_EQ(accepted, Esm::kMaxHooks - 1);  // the fixture registered one
}

TEST_F(EsmTest, SafeOpToOpRefusedByHookStaysSafeOp) {
  go_safeop();
  hooks.refuse_to = AlState::Op;
  hooks.refusal = AlStatusCode::NoSyncError;
  request(0x0008);
  EXPECT_EQ(status(), 0x0014);
  EXPECT_EQ(code(), 0x002D);
  EXPECT_FALSE(deactivated(2));
}

class EsmStrictOpTest : public EsmTest {
 protected:
  static EsmConfig strict() {
    EsmConfig c = test_esm_config();
    c.op_requires_outputs = true;
    return c;
  }
  EsmStrictOpTest() : EsmTest(strict()) {}
};

TEST_F(EsmStrictOpTest, OpNeedsOutputsFirst) {
  go_safeop();
  pdi.watchdog_expired(true);
  request(0x0008);
  EXPECT_EQ(status(), 0x0014);
  EXPECT_EQ(code(), 0x001B);
  pdi.watchdog_expired(false);
  request(0x0018);
  EXPECT_EQ(status(), 0x0008);
  EXPECT_EQ(code(), 0x0000);
}

}  // namespace
}  // namespace ecat::esc::test

namespace ecat::esc::test {
namespace {

struct Gate : EsmDeferral {
  bool open = false;
  bool transition_ready(AlState from, AlState to) noexcept override {
    (void)from;
    return open || to != AlState::Op;
  }
};

class EsmDeferralTest : public EsmTest {
 protected:
  EsmDeferralTest() { esm.add_deferral(gate); }
  Gate gate;
};

TEST_F(EsmDeferralTest, UpwardTransitionWaitsWithoutErrInd) {
  go_safeop();
  request(0x0008);
  EXPECT_EQ(status(), 0x0004);
  EXPECT_EQ(code(), 0x0000);
  EXPECT_EQ(esm.pending(), AlState::Op);
  esm.poll();
  EXPECT_EQ(status(), 0x0004);
  gate.open = true;
  esm.poll();
  EXPECT_EQ(status(), 0x0008);
  EXPECT_FALSE(esm.pending().has_value());
}

TEST_F(EsmDeferralTest, NewRequestReplacesThePendingOne) {
  go_safeop();
  request(0x0008);
  request(0x0002);
  EXPECT_EQ(status(), 0x0002);
  gate.open = true;
  esm.poll();
  EXPECT_EQ(status(), 0x0002);
}

TEST_F(EsmDeferralTest, HookGivingUpWhilePendingRefuses) {
  go_safeop();
  request(0x0008);
  hooks.refuse_to = AlState::Op;
  hooks.refusal = AlStatusCode::NoSyncError;
  esm.poll();
  EXPECT_EQ(status(), 0x0014);
  EXPECT_EQ(code(), 0x002D);
  EXPECT_FALSE(esm.pending().has_value());
}

TEST_F(EsmDeferralTest, DownwardTransitionsNeverWait) {
  gate.open = true;
  go_op();
  gate.open = false;
  request(0x0004);
  EXPECT_EQ(status(), 0x0004);
}

}  // namespace
}  // namespace ecat::esc::test
