// The DC faults of slave::FaultCatalogue (docs/faults.md "DC"): an
// oscillator drifting, a local time jump, SYNC0 stopped - on a line of two
// generic servos in DC Sync0 mode at 1 ms, the project's master cycling
// with its FRMW 0x0910 drift compensation, on simulated time. The figures
// are exact: the simulation has no jitter.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "common/le.hpp"
#include "master/coe_client.hpp"
#include "tests/slave/fault_rig.hpp"

namespace ecat::test {
namespace {

using std::chrono::milliseconds;

constexpr Nanoseconds kCycle = milliseconds(1);
constexpr std::uint32_t kCycleNs = 1'000'000;
constexpr std::uint16_t kSyncModeDcSync0 = 2;
constexpr std::uint16_t kSmOutputParameter = 0x1C32;
constexpr std::uint8_t kSmEventMissed = 0x0B;
constexpr std::uint16_t kSystemTimeDifference = 0x092C;  // bit 31: local copy behind
constexpr std::uint16_t kAlSafeOpErr = 0x0014, kAlOp = 0x0008;
constexpr std::uint16_t kDcSyncTimeoutError = 0x0034;
constexpr std::uint16_t kStartTimeCyclic = 0x0990;
constexpr std::uint16_t kActivation = 0x0981;  // next SYNC0 while active
constexpr Nanoseconds kLead = std::chrono::microseconds(500);

// 0x092C as a signed number of ns (bit 31 = sign, bits 30:0 = magnitude).
std::int64_t signed_difference(std::uint32_t reg) {
  const auto magnitude = static_cast<std::int64_t>(reg & 0x7FFFFFFFu);
  return (reg & 0x80000000u) != 0 ? -magnitude : magnitude;
}

// Two generic servos in DC Sync0 at 1 ms, in Op, the master cycling.
struct DcFaultRig : FaultRig {
  DcFaultRig() : FaultRig(2) {}

  std::string bring_up_dc() {
    auto n = master.scan();
    if (!n || *n != 2) return "scan";
    for (std::size_t i = 0; i < 2; ++i) {
      if (!master.slave(i).esc.has_dc()) return "no DC";
      if (!master.configure_mailbox(i)) return "mailbox";
      auto st = master.request_state(i, master::AlState::PreOp);
      if (!st || st->error()) return "preop";
      master::CoeClient coe(master, i);
      for (std::uint16_t obj : {std::uint16_t{0x1C32}, std::uint16_t{0x1C33}}) {
        if (!coe.download_value(obj, 1, kSyncModeDcSync0, 2)) return "sync mode";
      }
      if (!coe.read_pdo_sizes()) return "pdo sizes";
    }
    if (!master.configure_process_data()) return "process data";
    if (!master.configure_dc(clock.now())) return "dc";
    for (std::size_t i = 0; i < 2; ++i) {
      if (!master.configure_sync0(i, kCycleNs, 0, milliseconds(5))) return "sync0";
    }
    // The cycle's frame reaches the slaves kLead before each SYNC0, as a
    // phase-locked master sends it (docs/dc.md, master::DcPhaseLock).
    std::array<std::uint8_t, 8> b{};
    chain[0].esc().read(kStartTimeCyclic, b);
    const Nanoseconds pulse = chain[0].esc().dc().when_system(load_le<std::uint64_t>(b.data()));
    const Nanoseconds until = (pulse - clock.now()) % kCycle;
    next_ = clock.now() + (until - kLead + kCycle) % kCycle - kCycle;
    for (std::size_t i = 0; i < 2; ++i) {
      auto st = master.request_state(i, master::AlState::SafeOp);
      if (!st || st->error()) return "safeop";
    }
    for (int c = 0; c < 20; ++c) (void)tick();
    for (std::size_t i = 0; i < 2; ++i) {
      auto st = master.request_state(i, master::AlState::Op);
      if (!st || st->error()) return "op";
    }
    return "";
  }
  // One cycle on a fixed schedule (register reads between cycles do not
  // move it): the clock set to the next send time, then the exchange.
  bool tick() {
    next_ += kCycle;
    clock.set(std::max(next_, clock.now()));
    (void)chain.poll(clock.now());
    return master.exchange_process_data().has_value();
  }
  Nanoseconds next_{0};
  std::int64_t difference(std::size_t i) {
    auto v = master.fprd_u32(master.slave(i).station_address, kSystemTimeDifference);
    EXPECT_TRUE(v);
    return v ? signed_difference(*v) : INT64_MIN;
  }
  master::AlStatus al(std::size_t i) {
    auto s = master.read_al_status(i);
    EXPECT_TRUE(s);
    return s ? *s : master::AlStatus{};
  }
  std::uint32_t missed(std::size_t i) {
    master::CoeClient coe(master, i);
    return static_cast<std::uint32_t>(coe.upload_value(kSmOutputParameter, kSmEventMissed).value_or(0xFFFF));
  }
  // `n` cycles; the largest |0x092C| of slave 1 read after each.
  std::int64_t run(int n) {
    std::int64_t peak = 0;
    for (int c = 0; c < n; ++c) {
      EXPECT_TRUE(tick());
      peak = std::max(peak, std::abs(difference(1)));
    }
    return peak;
  }
};

// Let the time loop settle after the start-up (both oscillators exact).
void settle(DcFaultRig& r) {
  (void)r.run(500);
  ASSERT_EQ(r.difference(1), 0);
  ASSERT_EQ(r.missed(0), 0u);
  ASSERT_EQ(r.missed(1), 0u);
}

// A drift the ESC's time loop can follow (+500 ppm, inside its +-1000 ppm):
// 0x092C rises while the loop learns the rate, then returns to 0; the slave
// stays in Op and misses no SM event.
TEST(FaultDc, DriftWithinTheCorrectionRangeIsCorrected) {
  DcFaultRig r;
  const std::string up = r.bring_up_dc();
  if (up == "no DC") GTEST_SKIP() << "default device without DC";
  ASSERT_EQ(up, "");
  settle(r);
  const slave::FaultId id = r.engage("dc_drift", 1, {{"ppm", 500}});
  const std::int64_t peak = r.run(1000);
  EXPECT_EQ(peak, 11457);  // ns, while the loop learns the new rate
  EXPECT_EQ(r.difference(1), 0);
  EXPECT_EQ(r.al(1).raw, kAlOp);
  EXPECT_EQ(r.missed(1), 0u);
  ASSERT_TRUE(r.faults.clear(id));
}

// Beyond the range (+3000 ppm against a correction of at most -1000 ppm):
// the slave's system time runs away from the reference by 2 us per 1 ms
// cycle and 0x092C grows without bound.
TEST(FaultDc, DriftBeyondTheCorrectionRangeGrows) {
  DcFaultRig r;
  const std::string up = r.bring_up_dc();
  if (up == "no DC") GTEST_SKIP() << "default device without DC";
  ASSERT_EQ(up, "");
  settle(r);
  const slave::FaultId id = r.engage("dc_drift", 1, {{"ppm", 3000}});
  std::vector<std::int64_t> at;
  for (int k = 0; k < 5; ++k) {
    (void)r.run(100);
    at.push_back(r.difference(1));
  }
  // +2 000 ns per cycle: 3000 ppm less the saturated 1000 ppm correction.
  EXPECT_EQ(at, (std::vector<std::int64_t>{182189, 382173, 582173, 782173, 982173}));
  // The slave's SYNC0 wanders through the master's phase: after 250 cycles
  // (500 us) one SYNC0 comes without new outputs - one missed SM event,
  // which the default 10F1h:02 (4) tolerates: still Op.
  EXPECT_EQ(r.missed(1), 1u);
  EXPECT_EQ(r.al(1).raw, kAlOp);
  EXPECT_EQ(r.missed(0), 0u);
  ASSERT_TRUE(r.faults.clear(id));
}

// A time jump of +10 us: the next comparison sees it in 0x092C, then the
// loop slews it away at its rate limit.
TEST(FaultDc, TimeJumpShowsInTheDifference) {
  DcFaultRig r;
  const std::string up = r.bring_up_dc();
  if (up == "no DC") GTEST_SKIP() << "default device without DC";
  ASSERT_EQ(up, "");
  settle(r);
  const slave::FaultId id = r.engage("dc_time_jump", 1, {{"ns", 10'000}});
  std::vector<std::int64_t> d;
  for (int c = 0; c < 400; ++c) {
    ASSERT_TRUE(r.tick());
    d.push_back(r.difference(1));
  }
  int back = -1;
  for (int c = 0; c < 400; ++c) {
    if (std::abs(d[static_cast<std::size_t>(c)]) < 100 && back < 0) back = c;
    if (std::abs(d[static_cast<std::size_t>(c)]) >= 100) back = -1;
  }
  // The filter (0x0934 depth 4) shows 1/16 of the step at the first FRMW.
  EXPECT_EQ(d[0], 625);
  EXPECT_EQ(d[1], 1210);
  EXPECT_EQ(d[2], 1754);
  EXPECT_EQ(*std::max_element(d.begin(), d.end()), 6054);
  EXPECT_EQ(back, 311);  // cycles until |0x092C| < 100 ns for good
  EXPECT_EQ(r.missed(1), 0u);
  EXPECT_EQ(r.al(1).raw, kAlOp);
  ASSERT_TRUE(r.faults.clear(id));
}

// SYNC0 stopped with 0x0981 still activated: no SYNC0 reaches the firmware,
// so no SM event can be missed (1C32h:0B stays 0); after 3 SYNC0 cycles
// without one the slave drops to SafeOp | ErrInd with 0x0034 (DC sync
// timeout). Cleared, SYNC0 comes again and the master brings it back to Op.
TEST(FaultDc, Sync0StoppedDropsToSafeOpWithTheSyncTimeout) {
  DcFaultRig r;
  const std::string up = r.bring_up_dc();
  if (up == "no DC") GTEST_SKIP() << "default device without DC";
  ASSERT_EQ(up, "");
  (void)r.run(10);
  const slave::FaultId id = r.engage("sync0_stopped", 1);
  std::vector<std::uint16_t> states;
  for (int c = 0; c < 5; ++c) {
    ASSERT_TRUE(r.tick());
    states.push_back(r.al(1).raw);
  }
  EXPECT_EQ(states, (std::vector<std::uint16_t>{kAlOp, kAlOp, kAlSafeOpErr, kAlSafeOpErr, kAlSafeOpErr}));
  EXPECT_EQ(r.al(1).code, kDcSyncTimeoutError);
  EXPECT_EQ(r.missed(1), 0u);
  EXPECT_EQ(r.al(0).raw, kAlOp);
  // 0x0981 still shows the unit activated.
  auto activation = r.master.fprd_u8(r.master.slave(1).station_address, kActivation);
  ASSERT_TRUE(activation);
  EXPECT_EQ(*activation & 0x01, 0x01);

  ASSERT_TRUE(r.faults.clear(id));
  auto st = r.master.request_state(1, master::AlState::SafeOp, true);
  ASSERT_TRUE(st);
  EXPECT_EQ(st->raw, 0x0004);
  for (int c = 0; c < 5; ++c) ASSERT_TRUE(r.tick());
  st = r.master.request_state(1, master::AlState::Op);
  ASSERT_TRUE(st);
  EXPECT_EQ(st->raw, kAlOp);
  EXPECT_EQ(st->code, 0);
}

// Bad requests: nothing engaged.
TEST(FaultDc, RefusesBadRequests) {
  DcFaultRig r;
  const std::pair<slave::FaultRequest, std::string> bad[] = {
      {{"dc_drift", 1, std::nullopt, {}}, "dc_drift: parameter 'ppm' is required"},
      {{"dc_drift", 1, std::nullopt, {{"ppm", 0}}}, "dc_drift: ppm = 0 is out of range (-5000..5000, not 0)"},
      {{"dc_drift", 1, std::nullopt, {{"ppm", 5001}}}, "dc_drift: ppm = 5001 is out of range"},
      {{"dc_time_jump", 1, std::nullopt, {{"ns", 0}}}, "dc_time_jump: ns = 0 changes nothing"},
      {{"sync0_stopped", std::nullopt, std::nullopt, {}}, "sync0_stopped: needs a slave"},
      {{"sync0_stopped", 2, std::nullopt, {}}, "sync0_stopped: no slave 2"},
  };
  r.expect_refused(bad);
  const slave::FaultId id = r.engage("sync0_stopped", 0);
  auto again = r.faults.engage({"sync0_stopped", 0, std::nullopt, {}});
  ASSERT_FALSE(again);
  EXPECT_EQ(again.error(), "sync0_stopped: SYNC0 of slave 0 is already stopped");
  ASSERT_TRUE(r.faults.clear(id));
}

}  // namespace
}  // namespace ecat::test
