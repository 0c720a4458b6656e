// PreOp->SafeOp synchronisation checks with their exact AL status codes
// (ETG.1000.6 Table 11 names; rules in coe/sync_checks.hpp).
#include <gtest/gtest.h>

#include "coe/sync_checks.hpp"

namespace ecat::coe {
namespace {

using esc::AlStatusCode;

od::SyncLimits all_modes() {
  od::SyncLimits l;
  l.min_cycle_time_ns = 250'000;
  l.max_cycle_time_ns = 10'000'000;
  l.free_run = l.sm_synchronous = l.dc_sync0 = l.dc_sync1 = true;
  return l;
}

SyncSettings dc0() {
  SyncSettings s;
  s.output_mode = SyncMode::DcSync0;
  s.input_mode = SyncMode::DcSync0;
  s.dc_activation = 0x03;
  s.sync0_cycle = 1'000'000;
  return s;
}

TEST(SyncChecks, ValidConfigurationsPass) {
  EXPECT_EQ(check_sync_for_safeop(SyncSettings{}, all_modes()), AlStatusCode::NoError);  // free run
  SyncSettings sm;
  sm.output_mode = SyncMode::SmSynchronous;
  sm.input_mode = SyncMode::SmSynchronousSm2;
  EXPECT_EQ(check_sync_for_safeop(sm, all_modes()), AlStatusCode::NoError);
  EXPECT_EQ(check_sync_for_safeop(dc0(), all_modes()), AlStatusCode::NoError);
  SyncSettings dc1 = dc0();
  dc1.output_mode = SyncMode::DcSync1;
  dc1.dc_activation = 0x07;
  dc1.sync1_cycle = 300'000;
  EXPECT_EQ(check_sync_for_safeop(dc1, all_modes()), AlStatusCode::NoError);
  dc1.sync1_cycle = 3'000'000;  // multiple of SYNC0
  EXPECT_EQ(check_sync_for_safeop(dc1, all_modes()), AlStatusCode::NoError);
}

TEST(SyncChecks, FreeRunNotSupported0x0027) {
  od::SyncLimits l = all_modes();
  l.free_run = false;
  EXPECT_EQ(check_sync_for_safeop(SyncSettings{}, l), AlStatusCode::FreeRunNotSupported);
}

TEST(SyncChecks, SyncModeNotSupported0x0028) {
  od::SyncLimits l = all_modes();
  l.sm_synchronous = false;
  SyncSettings sm;
  sm.output_mode = SyncMode::SmSynchronous;
  EXPECT_EQ(check_sync_for_safeop(sm, l), AlStatusCode::SyncModeNotSupported);
  l = all_modes();
  l.dc_sync0 = false;
  EXPECT_EQ(check_sync_for_safeop(dc0(), l), AlStatusCode::SyncModeNotSupported);
  l = all_modes();
  l.dc_sync1 = false;
  SyncSettings dc1 = dc0();
  dc1.input_mode = SyncMode::DcSync1;
  dc1.dc_activation = 0x07;
  EXPECT_EQ(check_sync_for_safeop(dc1, l), AlStatusCode::SyncModeNotSupported);
  SyncSettings sm2_on_outputs;
  sm2_on_outputs.output_mode = SyncMode::SmSynchronousSm2;
  EXPECT_EQ(check_sync_for_safeop(sm2_on_outputs, all_modes()), AlStatusCode::SyncModeNotSupported);
  SyncSettings sm2_without_outputs;
  sm2_without_outputs.has_outputs = false;
  sm2_without_outputs.input_mode = SyncMode::SmSynchronousSm2;
  EXPECT_EQ(check_sync_for_safeop(sm2_without_outputs, all_modes()), AlStatusCode::SyncModeNotSupported);
  SyncSettings undefined;
  undefined.output_mode = static_cast<SyncMode>(7);
  EXPECT_EQ(check_sync_for_safeop(undefined, all_modes()), AlStatusCode::SyncModeNotSupported);
}

TEST(SyncChecks, FreeRunNeeds3Buffer0x0029) {
  SyncSettings s;
  s.outputs_three_buffer = false;
  EXPECT_EQ(check_sync_for_safeop(s, all_modes()), AlStatusCode::FreeRunNeeds3BufferMode);
  s.has_outputs = false;  // inputs alone do not care
  EXPECT_EQ(check_sync_for_safeop(s, all_modes()), AlStatusCode::NoError);
}

TEST(SyncChecks, InvalidDcSyncConfiguration0x0030) {
  SyncSettings s = dc0();
  s.dc_activation = 0x00;  // DC mode, SYNC unit off
  EXPECT_EQ(check_sync_for_safeop(s, all_modes()), AlStatusCode::InvalidDcSyncConfiguration);
  s.dc_activation = 0x01;  // unit on, SYNC0 off
  EXPECT_EQ(check_sync_for_safeop(s, all_modes()), AlStatusCode::InvalidDcSyncConfiguration);
  s = dc0();
  s.output_mode = SyncMode::DcSync1;  // SYNC1 mode, SYNC1 off
  EXPECT_EQ(check_sync_for_safeop(s, all_modes()), AlStatusCode::InvalidDcSyncConfiguration);
  SyncSettings free_run_with_sync;
  free_run_with_sync.dc_activation = 0x03;
  EXPECT_EQ(check_sync_for_safeop(free_run_with_sync, all_modes()), AlStatusCode::InvalidDcSyncConfiguration);
}

TEST(SyncChecks, DcInvalidSyncCycleTime0x0035) {
  SyncSettings s = dc0();
  s.sync0_cycle = 0;  // single shot
  EXPECT_EQ(check_sync_for_safeop(s, all_modes()), AlStatusCode::DcInvalidSyncCycleTime);
  s = dc0();
  s.cycle_time = 2'000'000;  // 1C32h:02 disagrees with 0x09A0
  EXPECT_EQ(check_sync_for_safeop(s, all_modes()), AlStatusCode::DcInvalidSyncCycleTime);
  s.cycle_time = 1'000'000;
  EXPECT_EQ(check_sync_for_safeop(s, all_modes()), AlStatusCode::NoError);
}

TEST(SyncChecks, DcSync0CycleTime0x0036) {
  SyncSettings s = dc0();
  s.sync0_cycle = 249'999;
  EXPECT_EQ(check_sync_for_safeop(s, all_modes()), AlStatusCode::DcSync0CycleTime);
  s.sync0_cycle = 250'000;
  EXPECT_EQ(check_sync_for_safeop(s, all_modes()), AlStatusCode::NoError);
  s.sync0_cycle = 10'000'001;
  EXPECT_EQ(check_sync_for_safeop(s, all_modes()), AlStatusCode::DcSync0CycleTime);
}

TEST(SyncChecks, DcSync1CycleTime0x0037) {
  SyncSettings s = dc0();
  s.output_mode = SyncMode::DcSync1;
  s.dc_activation = 0x07;
  s.sync1_cycle = 2'500'000;  // longer than SYNC0 and not a multiple
  EXPECT_EQ(check_sync_for_safeop(s, all_modes()), AlStatusCode::DcSync1CycleTime);
}

TEST(SyncChecks, DeriveModeFromRegistersWhenNotWritten) {
  const od::SyncLimits l = all_modes();
  EXPECT_EQ(derive_sync_mode(false, SyncMode::FreeRun, 0x03, l, SyncMode::SmSynchronous), SyncMode::DcSync0);
  EXPECT_EQ(derive_sync_mode(true, SyncMode::FreeRun, 0x03, l, SyncMode::SmSynchronous), SyncMode::FreeRun);
  EXPECT_EQ(derive_sync_mode(false, SyncMode::DcSync0, 0x00, l, SyncMode::SmSynchronousSm2),
            SyncMode::SmSynchronousSm2);
  od::SyncLimits no_sm = l;
  no_sm.sm_synchronous = false;
  EXPECT_EQ(derive_sync_mode(false, SyncMode::DcSync0, 0x00, no_sm, SyncMode::SmSynchronous), SyncMode::FreeRun);
  EXPECT_EQ(derive_sync_mode(false, SyncMode::SmSynchronous, 0x00, l, SyncMode::SmSynchronous),
            SyncMode::SmSynchronous);
}

TEST(SyncChecks, DefinedModes) {
  EXPECT_TRUE(is_defined_sync_mode(0x22, true));
  EXPECT_FALSE(is_defined_sync_mode(0x22, false));
  EXPECT_FALSE(is_defined_sync_mode(4, false));
  EXPECT_TRUE(is_dc(SyncMode::DcSync1));
  EXPECT_FALSE(is_dc(SyncMode::SmSynchronous));
}

}  // namespace
}  // namespace ecat::coe
