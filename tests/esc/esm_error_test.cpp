// Error indication and acknowledge (esm-al-codes.md §5), run-time fall-backs
// (watchdog 0x001B, SM changes 0x0016/0x001D), raise_error and device
// identification (AL control bit 5).
#include <gtest/gtest.h>

#include "esm_fixture.hpp"

namespace ecat::esc::test {
namespace {

TEST_F(EsmTest, RequestWithoutAckIsIgnoredWhileErrIndIsSet) {
  request(0x0002);  // no mailbox configured
  ASSERT_EQ(status(), 0x0011);
  ASSERT_EQ(code(), 0x0016);
  mailbox_sms();
  request(0x0002);
  EXPECT_EQ(status(), 0x0011);
  EXPECT_EQ(code(), 0x0016);
  EXPECT_EQ(pdi.events() & kAlEventAlControl, 0u);  // read anyway
}

TEST_F(EsmTest, AckWithNextStateCarriesOutTheTransition) {
  request(0x0002);
  mailbox_sms();
  request(0x0012);
  EXPECT_EQ(status(), 0x0002);
  EXPECT_EQ(code(), 0x0000);
}

TEST_F(EsmTest, AckOfCurrentStateClearsErrIndAndCode) {
  go_preop();
  request(0x0008);
  ASSERT_EQ(status(), 0x0012);
  request(0x0012);  // IgH: writes back the status it read
  EXPECT_EQ(status(), 0x0002);
  EXPECT_EQ(code(), 0x0000);
}

TEST_F(EsmTest, InitRequestActsAsAcknowledge) {
  go_preop();
  request(0x0008);
  request(0x0001);
  EXPECT_EQ(status(), 0x0001);
  EXPECT_EQ(code(), 0x0000);
}

TEST_F(EsmTest, AckButNewCheckFailsSetsTheNewCode) {
  go_preop();
  request(0x0008);
  ASSERT_EQ(code(), 0x0011);
  pdi.master_sm(3, 0x1300, 4, kInControl, true);
  request(0x0014);
  EXPECT_EQ(status(), 0x0012);
  EXPECT_EQ(code(), 0x001E);
}

TEST_F(EsmTest, WatchdogExpiryInOpFallsToSafeOp) {
  go_op();
  pdi.watchdog_expired(true);
  esm.poll();
  EXPECT_EQ(status(), 0x0014);
  EXPECT_EQ(code(), 0x001B);
  EXPECT_FALSE(deactivated(2));  // SafeOp keeps the process SMs
  ASSERT_FALSE(hooks.changes.empty());
  EXPECT_EQ(hooks.changes.back().from, AlState::Op);
  EXPECT_EQ(hooks.changes.back().to, AlState::SafeOp);
  EXPECT_EQ(hooks.changes.back().code, AlStatusCode::SyncManagerWatchdog);
  // The master acknowledges and goes back to Op once outputs flow again.
  pdi.watchdog_expired(false);
  request(0x0018);
  EXPECT_EQ(status(), 0x0008);
  EXPECT_EQ(code(), 0x0000);
}

TEST_F(EsmTest, WatchdogStatusPolledInOpEvenWithoutEvent) {
  go_op();
  pdi.poke_u16(reg::kWatchdogStatusProcessData, 0);
  esm.poll();
  EXPECT_EQ(status(), 0x0014);
  EXPECT_EQ(code(), 0x001B);
}

TEST_F(EsmTest, WatchdogExpiryOutsideOpIsOnlyConsumed) {
  go_safeop();
  pdi.watchdog_expired(true);
  esm.poll();
  EXPECT_EQ(status(), 0x0004);
  EXPECT_EQ(pdi.events() & kAlEventWatchdog, 0u);
}

TEST_F(EsmTest, MailboxChangedInSafeOpFallsToInit) {
  go_safeop();
  pdi.master_sm(0, kMbxOutStart, 64, kMbxOutControl, true);
  esm.poll();
  EXPECT_EQ(status(), 0x0011);
  EXPECT_EQ(code(), 0x0016);
  for (unsigned sm = 0; sm < 4; ++sm) EXPECT_TRUE(deactivated(sm)) << sm;
  EXPECT_EQ(pdi.events() & kAlEventSmActivation, 0u);
}

TEST_F(EsmTest, MailboxRepeatToggleIsNotAnError) {
  go_preop();
  pdi.master_sm(1, kMbxInStart, kMbxLength, kMbxInControl, true);  // same values again
  esm.poll();
  EXPECT_EQ(status(), 0x0002);
  EXPECT_EQ(code(), 0x0000);
}

TEST_F(EsmTest, OutputSmDisabledInOpFallsToPreOp) {
  go_op();
  pdi.master_sm(2, kOutStart, 4, kOutControl, false);
  esm.poll();
  EXPECT_EQ(status(), 0x0012);
  EXPECT_EQ(code(), 0x001D);
  EXPECT_TRUE(deactivated(2));
}

TEST_F(EsmTest, ProcessSmChangesInPreOpAreFine) {
  go_preop();
  pdi.master_sm(2, 0x1400, 4, kOutControl, true);
  esm.poll();
  EXPECT_EQ(status(), 0x0002);
}

TEST_F(EsmTest, RaiseErrorDropsToTarget) {
  go_op();
  esm.raise_error(AlStatusCode::SynchronizationError, AlState::SafeOp);
  EXPECT_EQ(status(), 0x0014);
  EXPECT_EQ(code(), 0x001A);
  EXPECT_EQ(esm.state(), AlState::SafeOp);
  EXPECT_TRUE(esm.error_indicated());
  EXPECT_EQ(esm.status_code(), AlStatusCode::SynchronizationError);
}

TEST_F(EsmTest, RaiseErrorNeverGoesUp) {
  go_preop();
  esm.raise_error(AlStatusCode::SynchronizationError, AlState::Op);
  EXPECT_EQ(status(), 0x0012);
  EXPECT_EQ(code(), 0x001A);
}

TEST_F(EsmTest, CodeIsClearedByTheNextSuccessfulTransition) {
  go_op();
  esm.raise_error(AlStatusCode::SynchronizationError, AlState::SafeOp);
  request(0x0012);  // ack with a lower state
  EXPECT_EQ(status(), 0x0002);
  EXPECT_EQ(code(), 0x0000);
}

TEST_F(EsmTest, DeviceIdentificationFromAlias) {
  pdi.poke_u16(reg::kConfiguredStationAlias, 0x1234);
  mailbox_sms();
  request(0x0022);
  EXPECT_EQ(status(), 0x0022);
  EXPECT_EQ(code(), 0x1234);
  request(0x0002);  // request without bit 5 clears it
  EXPECT_EQ(status(), 0x0002);
  EXPECT_EQ(code(), 0x0000);
}

TEST_F(EsmTest, DeviceIdentificationZeroIsNotReported) {
  request(0x0021);
  EXPECT_EQ(status(), 0x0001);
  EXPECT_EQ(code(), 0x0000);
}

TEST_F(EsmTest, DeviceIdentificationNotWhileRefusing) {
  pdi.poke_u16(reg::kConfiguredStationAlias, 0x1234);
  request(0x0022);  // mailbox not configured
  EXPECT_EQ(status(), 0x0011);
  EXPECT_EQ(code(), 0x0016);
}

class EsmDeviceIdTest : public EsmTest {
 protected:
  static EsmConfig with_id() {
    EsmConfig c = test_esm_config();
    c.device_id = 0x00A5;
    return c;
  }
  EsmDeviceIdTest() : EsmTest(with_id()) {}
};

TEST_F(EsmDeviceIdTest, ApplicationValueWinsOverAlias) {
  pdi.poke_u16(reg::kConfiguredStationAlias, 0x1234);
  request(0x0021);
  EXPECT_EQ(status(), 0x0021);
  EXPECT_EQ(code(), 0x00A5);
}

TEST(AlStatusCodeText, DescribesCodesAndStates) {
  EXPECT_EQ(describe(AlStatusCode::InvalidRequestedStateChange), "Invalid requested state change");
  EXPECT_EQ(describe(AlStatusCode::SyncManagerWatchdog), "Sync manager watchdog");
  EXPECT_EQ(describe(static_cast<AlStatusCode>(0x8001)), "Vendor specific error");
  EXPECT_EQ(describe(static_cast<AlStatusCode>(0x0099)), "Reserved AL status code");
  EXPECT_EQ(describe(AlState::SafeOp), "SAFEOP");
  EXPECT_EQ(describe(static_cast<AlState>(7)), "UNKNOWN");
}

}  // namespace
}  // namespace ecat::esc::test
