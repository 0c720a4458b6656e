// How often the slaves read their clock (esc::Esc::pin_pdi_time): in a live
// run every read is a call into the vDSO (~30 ns on the project's VM), and
// the firmware's accesses to its ESC each read it until a firmware run
// pinned one time for all of them. Two generic servos in Op in free run
// under the project's master: across 50 cycles the chain's clock is read
// exactly once per firmware run (before: 3 a run with an application cycle,
// the PDI's reads of 0x0220 and SM2 and the commit of SM3), and each drive
// ran one application cycle a cycle.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>

#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

using namespace std::chrono_literals;

constexpr std::size_t kDrives = 2;
constexpr int kCycles = 50;

struct Counts {
  std::uint64_t reads = 0;
  std::uint64_t runs = 0;
  std::uint64_t application_cycles = 0;
};

Counts counts(const InProcess& p) {
  Counts c;
  c.reads = p.chain_clock.reads();
  for (std::size_t i = 0; i < kDrives; ++i) {
    const slave::SlaveStatus s = p.chain[i].status();
    c.runs += s.firmware_polls;
    c.application_cycles += s.application_cycles;
  }
  return c;
}

TEST(FirmwareClockReads, OneReadOfTheClockPerFirmwareRun) {
  InProcess p;
  p.add_default(kDrives);
  ASSERT_EQ(p.bring_up(), "");
  for (int c = 0; c < 5; ++c) ASSERT_TRUE(p.cycle_once(1ms));
  const Counts before = counts(p);
  for (int c = 0; c < kCycles; ++c) {
    auto r = p.cycle_once(1ms);
    ASSERT_TRUE(r);
  }
  const Counts after = counts(p);
  EXPECT_EQ(after.application_cycles - before.application_cycles, kDrives * kCycles);
  ASSERT_GE(after.runs - before.runs, kDrives * kCycles);
  EXPECT_EQ(after.reads - before.reads, after.runs - before.runs);
}

}  // namespace
}  // namespace ecat::test
