// STYLE lesson 11: the cyclic path allocates nothing - the ESM poll, the sync
// controller's poll and the DC unit's register accesses and poll, over many
// DC cycles in Op with SYNC events, missed events and counter updates.
#include <gtest/gtest.h>

#include "esc/dc/dc_unit.hpp"
#include "sync_fixture.hpp"
#include "tests/support/alloc_counter.hpp"

namespace ecat::coe::test {
namespace {

TEST_F(SyncTest, CyclicPathAllocatesNothing) {
  go_dc_op();
  esc::DcUnit unit;
  unit.set_clock(50.0, 1000);
  unit.reset(100);
  std::array<std::uint8_t, 8> b{};
  std::size_t allocations = 0;
  {
    ecat::test::AllocCounter counter;
    for (int c = 0; c < 1000; ++c) {
      t += kCycle;
      if (c % 7 != 0) new_outputs();
      sync0(t);
      esm.poll();
      unit.write(esc::dcreg::kSystemTime, b, t);
      unit.read(esc::dcreg::kSystemTimeDifference, std::span<std::uint8_t>(b.data(), 4), t);
      (void)unit.poll(t);
    }
    allocations = counter.count();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(sync.sm_events_missed(), 0u);
}

}  // namespace
}  // namespace ecat::coe::test
