// 1C32h/1C33h at run time over the fake PDI with the real ESM: SDO write
// checks, the ESM refusals (0x0030, 0x002D), mode derivation from 0x0981,
// application cycle triggers per mode, counters 0Bh/0Ch/0Dh/20h and the
// run-time drops (0x001A, 0x0034, 0x002C).
#include <gtest/gtest.h>

#include "sync_fixture.hpp"

namespace ecat::coe::test {
namespace {

TEST_F(SyncTest, InstallFillsSupportedModesAndMinimumCycle) {
  EXPECT_EQ(store.get<std::uint16_t>(kSmOutputParameter, syncsub::kSyncModesSupported), 0x0027u);
  EXPECT_EQ(store.get<std::uint32_t>(kSmInputParameter, syncsub::kMinimumCycleTime), 250'000u);
}

TEST_F(SyncTest, SdoWritesOfUndefinedModesAreRefused) {
  EXPECT_EQ(sdo_write(kSmOutputParameter, 1, 5, 2).error(), SdoAbort::ValueRange);
  EXPECT_EQ(sdo_write(kSmOutputParameter, 1, 0x22, 2).error(), SdoAbort::ValueRange);
  EXPECT_TRUE(sdo_write(kSmInputParameter, 1, 0x22, 2).has_value());
  EXPECT_EQ(sync.input_mode(), SyncMode::SmSynchronousSm2);
  EXPECT_EQ(sdo_write(kSmOutputParameter, 8, 3, 2).error(), SdoAbort::ValueRange);
}

TEST_F(SyncTest, DcModeNeedsActivatedSyncUnit0x0030) {
  go_preop();
  ASSERT_TRUE(sdo_write(kSmOutputParameter, 1, 2, 2).has_value());
  dc_registers(0x00, 1'000'000);
  request(0x0004);
  EXPECT_EQ(status(), 0x0012);
  EXPECT_EQ(code(), 0x0030);
}

TEST_F(SyncTest, CycleBelowMinimum0x0036) {
  go_preop();
  ASSERT_TRUE(sdo_write(kSmOutputParameter, 1, 2, 2).has_value());
  dc_registers(0x03, 100'000);
  request(0x0004);
  EXPECT_EQ(code(), 0x0036);
}

TEST_F(SyncTest, ModeDerivedFromSyncActivationWhenNotWritten) {
  go_preop();
  dc_registers(0x03, 1'000'000);
  request(0x0004);
  EXPECT_EQ(status(), 0x0004);
  EXPECT_EQ(store.get<std::uint16_t>(kSmOutputParameter, syncsub::kSyncMode), 2u);
  EXPECT_EQ(store.get<std::uint16_t>(kSmInputParameter, syncsub::kSyncMode), 2u);
}

TEST_F(SyncTest, InputsFollowWrittenOutputMode) {
  go_preop();
  ASSERT_TRUE(sdo_write(kSmOutputParameter, 1, 1, 2).has_value());
  request(0x0004);
  EXPECT_EQ(status(), 0x0004);
  EXPECT_EQ(store.get<std::uint16_t>(kSmInputParameter, syncsub::kSyncMode), 0x22u);
}

TEST_F(SyncTest, OpWaitsUntilSynchronised) {
  go_preop();
  ASSERT_TRUE(sdo_write(kSmOutputParameter, 1, 2, 2).has_value());
  dc_registers(0x03, 1'000'000);
  request(0x0004);
  request(0x0008);
  EXPECT_EQ(status(), 0x0004);  // pending: no ErrInd, the master keeps polling
  EXPECT_EQ(code(), 0x0000);
  EXPECT_EQ(esm.pending(), esc::AlState::Op);
  EXPECT_TRUE(sync0(t += kCycle).run);
  esm.poll();
  EXPECT_EQ(status(), 0x0004);
  EXPECT_TRUE(sync0(t += kCycle).run);
  esm.poll();
  EXPECT_EQ(status(), 0x0008);
  EXPECT_EQ(code(), 0x0000);
}

TEST_F(SyncTest, NeverSynchronised0x002D) {
  go_preop();
  ASSERT_TRUE(sdo_write(kSmOutputParameter, 1, 2, 2).has_value());
  dc_registers(0x03, 1'000'000);
  request(0x0004);
  sync.poll(t);
  request(0x0008);
  sync.poll(t += SyncController::kSyncWaitTimeout - Nanoseconds{1});
  esm.poll();
  EXPECT_EQ(status(), 0x0004);
  sync.poll(t += Nanoseconds{1});
  esm.poll();
  EXPECT_EQ(status(), 0x0014);
  EXPECT_EQ(code(), 0x002D);
}

TEST_F(SyncTest, DcCycleRunsOnSync0Only) {
  go_dc_op();
  EXPECT_FALSE(sync.poll(t += Nanoseconds{10'000}).run);
  new_outputs();
  EXPECT_FALSE(sync.poll(t += Nanoseconds{10'000}).run);  // outputs alone do not start it
  EXPECT_TRUE(sync0(t += kCycle).run);
  EXPECT_EQ(pdi.events() & esc::dcreg::kAlEventSync0, 0u);  // acknowledged via 0x098E
}

TEST_F(SyncTest, MissedSmEventsCountAndDropToSafeOp0x001A) {
  go_dc_op();
  new_outputs();
  sync0(t += kCycle);
  EXPECT_EQ(store.get<std::uint16_t>(kSmOutputParameter, syncsub::kSmEventMissed), 0u);
  sync0(t += kCycle);  // master skipped a cycle
  EXPECT_EQ(store.get<std::uint16_t>(kSmOutputParameter, syncsub::kSmEventMissed), 1u);
  EXPECT_EQ(store.get<std::uint8_t>(kSmOutputParameter, syncsub::kSyncError), 1u);
  EXPECT_EQ(sync.sm_events_missed(), 1u);
  EXPECT_EQ(status(), 0x0008);  // 3 <= limit 4
  new_outputs();
  sync0(t += kCycle);  // good cycle: counter 2
  EXPECT_EQ(store.get<std::uint8_t>(kSmOutputParameter, syncsub::kSyncError), 0u);
  sync0(t += kCycle);  // miss: 5 > 4
  EXPECT_EQ(status(), 0x0014);
  EXPECT_EQ(code(), 0x001A);
  EXPECT_EQ(store.get<std::uint16_t>(kSmInputParameter, syncsub::kSmEventMissed), 2u);
}

// Good DC cycles change no counter, so they write nothing to 1C32h/1C33h:
// each write moves the store's generation, and a drive's binding then reads
// every entry again (issue 30: in DC mode every SYNC cycle did). A missed SM
// event is written at once.
TEST_F(SyncTest, GoodDcCyclesLeaveTheStoreAsItWas) {
  go_dc_op();
  sync0(t += kCycle);  // takes the buffer written before Op
  const std::uint64_t before = store.generation();
  for (int k = 0; k < 5; ++k) {
    new_outputs();
    ASSERT_TRUE(sync0(t += kCycle).run);
  }
  EXPECT_EQ(store.generation(), before);
  EXPECT_EQ(sync.sm_events_missed(), 0u);
  sync0(t += kCycle);  // no new outputs: missed
  EXPECT_NE(store.generation(), before);
  EXPECT_EQ(store.get<std::uint16_t>(kSmOutputParameter, syncsub::kSmEventMissed), 1u);
  EXPECT_EQ(store.get<std::uint16_t>(kSmInputParameter, syncsub::kSmEventMissed), 1u);
  EXPECT_EQ(store.get<std::uint8_t>(kSmOutputParameter, syncsub::kSyncError), 1u);
}

// The Yaskawa Sigma-V manual's example (seeds/digests/yaskawa-sigma5-sd-coe.md
// 2.4, 10F1h:02 = 9): SM2 events 1 0 1 0 1 0 1 0 give the counter
// 0 3 2 5 4 7 6 9, and the drive trips when it *reaches* the limit, on the
// 8th DC cycle. Beckhoff's SSC also calls the sequence invalid once the
// counter is >= 10F1h:02 (docs/dc.md).
TEST_F(SyncTest, SyncErrorWhenTheCounterReachesTheLimitAsInTheYaskawaExample) {
  ASSERT_TRUE(sdo_write(kErrorSettings, kErrorSettingsSyncErrorLimit, 9, 2).has_value());
  go_dc_op();  // outputs written before Op: the first SYNC0 in Op is good
  for (int k = 0; k < 7; ++k) {
    if (k % 2 == 0 && k > 0) new_outputs();  // k = 0: the buffer written before Op is taken here
    sync0(t += kCycle);
    ASSERT_EQ(status(), 0x0008) << "DC cycle " << k + 1;
  }
  sync0(t += kCycle);  // 8th: a miss, counter 6 + 3 = 9 = limit
  EXPECT_EQ(status(), 0x0014);
  EXPECT_EQ(code(), 0x001A);
  EXPECT_EQ(sync.sm_events_missed(), 4u);
}

// 10F1h:02 = 0: no sync error detection (SSC V5.13, the Yaskawa manual);
// the missed events are still counted in 1C32h:0Bh.
TEST_F(SyncTest, LimitZeroSwitchesTheSyncErrorOff) {
  ASSERT_TRUE(sdo_write(kErrorSettings, kErrorSettingsSyncErrorLimit, 0, 2).has_value());
  go_dc_op();
  sync0(t += kCycle);
  for (int k = 0; k < 10; ++k) sync0(t += kCycle);
  EXPECT_EQ(status(), 0x0008);
  EXPECT_EQ(sync.sm_events_missed(), 10u);
  EXPECT_EQ(store.get<std::uint16_t>(kSmOutputParameter, syncsub::kSmEventMissed), 10u);
}

TEST_F(SyncTest, CounterResetBySubindex8) {
  go_dc_op();
  sync0(t += kCycle);  // takes the buffer written before Op
  sync0(t += kCycle);
  ASSERT_EQ(sync.sm_events_missed(), 1u);
  ASSERT_TRUE(sdo_write(kSmOutputParameter, 8, 2, 2).has_value());
  EXPECT_EQ(sync.sm_events_missed(), 0u);
  EXPECT_EQ(store.get<std::uint16_t>(kSmOutputParameter, syncsub::kSmEventMissed), 0u);
  EXPECT_EQ(store.get<std::uint16_t>(kSmOutputParameter, syncsub::kGetCycleTime), 0u);
}

TEST_F(SyncTest, SyncTimeoutInOp0x0034) {
  go_dc_op();
  new_outputs();
  sync0(t += kCycle);
  const SyncPoll p = sync.poll(t += kCycle);
  ASSERT_TRUE(p.next.has_value());
  EXPECT_EQ(*p.next, t - kCycle + 3 * kCycle);
  sync.poll(*p.next);
  EXPECT_EQ(status(), 0x0014);
  EXPECT_EQ(code(), 0x0034);
}

// A SYNC0 pulse latched while the slave was in PreOp (a master that left the
// SYNC unit running from an earlier Op down to Init, then programmed a new
// start 20 ms ahead) is no pulse of the new run: it neither counts towards Op
// nor starts the SYNC timeout, which would drop SafeOp with 0x0034 long
// before the first real pulse.
TEST_F(SyncTest, PulseLatchedBeforeSafeOpIsNotASyncEvent) {
  go_preop();
  ASSERT_TRUE(sdo_write(kSmOutputParameter, 1, 2, 2).has_value());
  pdi.raise_event(esc::dcreg::kAlEventSync0);  // the old run's last pulse, unread
  dc_registers(0x03, 1'000'000);
  request(0x0004);
  ASSERT_EQ(status(), 0x0004);
  EXPECT_EQ(pdi.events() & esc::dcreg::kAlEventSync0, 0u);  // acknowledged via 0x098E at PreOp->SafeOp
  EXPECT_FALSE(sync.poll(t += kCycle).run);
  sync.poll(t += 5 * kCycle);
  EXPECT_EQ(status(), 0x0004);  // no SYNC timeout: SYNC has not started
  EXPECT_EQ(code(), 0x0000);
  EXPECT_TRUE(sync0(t += kCycle).run);  // the first real pulse counts
}

TEST_F(SyncTest, SyncUnitSwitchedOffInOp0x002C) {
  go_dc_op();
  new_outputs();
  sync0(t += kCycle);
  pdi.poke_u8(dc(esc::dcreg::kActivation), 0x00);
  sync.poll(t += 3 * kCycle);
  EXPECT_EQ(status(), 0x0014);
  EXPECT_EQ(code(), 0x002C);
}

TEST_F(SyncTest, ShiftTimeTooShortCounted) {
  go_dc_op();
  ASSERT_TRUE(store.set(kSmOutputParameter, syncsub::kCalcAndCopyTime, std::uint32_t{100'000}).has_value());
  pdi.poke_u64(dc(esc::dcreg::kSystemTime), 5'000'000);
  pdi.poke_u64(dc(esc::dcreg::kStartTimeCyclicOperation), 5'050'000);  // next SYNC0 in 50 µs
  new_outputs();
  sync.poll(t += Nanoseconds{1000});
  EXPECT_EQ(store.get<std::uint16_t>(kSmOutputParameter, syncsub::kShiftTimeTooShort), 1u);
  pdi.poke_u64(dc(esc::dcreg::kStartTimeCyclicOperation), 5'500'000);  // 500 µs: fine
  new_outputs();
  sync.poll(t += Nanoseconds{1000});
  EXPECT_EQ(sync.shift_time_too_short(), 1u);
}

// Without a calc-and-copy time (1C32h:06 = 0, the profile's default) no
// outputs come too late: the firmware does not read the system time and
// the next SYNC0 time for the check (issue 30); with one it reads both.
TEST_F(SyncTest, ShiftTimeCheckReadsTheDcRegistersOnlyWithACalcAndCopyTime) {
  go_dc_op();
  const std::uint16_t system = dc(esc::dcreg::kSystemTime);
  const std::uint16_t next = dc(esc::dcreg::kStartTimeCyclicOperation);
  const unsigned before = pdi.dc_reads(system);
  new_outputs();
  sync.poll(t += Nanoseconds{1000});
  EXPECT_EQ(pdi.dc_reads(system), before);
  EXPECT_EQ(pdi.dc_reads(next), 0u);
  ASSERT_TRUE(store.set(kSmOutputParameter, syncsub::kCalcAndCopyTime, std::uint32_t{100'000}).has_value());
  new_outputs();
  sync.poll(t += Nanoseconds{1000});
  EXPECT_EQ(pdi.dc_reads(system), before + 1);
  EXPECT_EQ(pdi.dc_reads(next), 1u);
}

TEST_F(SyncTest, SmSynchronousRunsOnNewOutputs) {
  go_preop();
  ASSERT_TRUE(sdo_write(kSmOutputParameter, 1, 1, 2).has_value());
  request(0x0004);
  ASSERT_EQ(status(), 0x0004);
  EXPECT_FALSE(sync.poll(t += kCycle).run);
  new_outputs();
  EXPECT_TRUE(sync.poll(t += kCycle).run);
  EXPECT_FALSE(sync.poll(t += kCycle).run);  // same buffer
  request(0x0008);
  new_outputs();
  EXPECT_TRUE(sync.poll(t += Nanoseconds{100'000}).run);
  new_outputs();
  EXPECT_TRUE(sync.poll(t += Nanoseconds{100'000}).run);  // faster than the 250 µs minimum
  EXPECT_EQ(store.get<std::uint16_t>(kSmOutputParameter, syncsub::kCycleTimeTooSmall), 1u);
}

TEST_F(SyncTest, FreeRunUsesCycleTime) {
  ASSERT_TRUE(sdo_write(kSmOutputParameter, 2, 2'000'000, 4).has_value());
  go_preop();
  request(0x0004);
  ASSERT_EQ(status(), 0x0004);
  SyncPoll p = sync.poll(t);
  EXPECT_TRUE(p.run);
  EXPECT_EQ(p.next, t + Nanoseconds{2'000'000});
  EXPECT_FALSE(sync.poll(t + Nanoseconds{1'999'999}).run);
  EXPECT_TRUE(sync.poll(t + Nanoseconds{2'000'000}).run);
}

}  // namespace
}  // namespace ecat::coe::test
