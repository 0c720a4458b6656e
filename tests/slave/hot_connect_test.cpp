// The master's hot connect (master/hot_connect.cpp, SOEM's ec_recover_slave
// + ec_reconfig_slave): a slave power cycled in Op (fault power_cycle) is
// found at its position with station address 0, checked against the scan's
// identity through the temporary address 0xFFFF, addressed again, and with
// its mailbox, PreOp, process-data SMs and FMMUs set up again it returns to
// Op with the cycle's full WKC; another device at the position is refused.
#include <gtest/gtest.h>

#include "common/le.hpp"
#include "master/coe_client.hpp"
#include "master/registers.hpp"
#include "tests/slave/fault_rig.hpp"

namespace ecat::test {
namespace {

using namespace std::chrono_literals;
constexpr Nanoseconds kCycle = 1ms;

std::uint16_t station_at(InProcess& r, std::size_t position) {
  std::uint8_t a[2]{};
  auto wkc = r.master.transact(Command::Aprd,
                               device_address(auto_increment_adp(static_cast<std::uint16_t>(position)),
                                              master::reg::kConfiguredStationAddress),
                               a);
  EXPECT_TRUE(wkc && *wkc == 1);
  return load_le<std::uint16_t>(a);
}

TEST(HotConnect, APowerCycledSlaveIsAddressedAndConfiguredAgain) {
  FaultRig r(3);
  ASSERT_EQ(r.bring_up(kCycle), "");
  const std::uint16_t expected = r.master.expected_wkc();
  ASSERT_EQ(expected, 9u);  // LRW: 3 per slave
  ASSERT_EQ(r.master.readdress(1).value_or(true), false) << "still at its address: nothing to do";

  const slave::FaultId off = r.engage("power_cycle", 1);
  for (int c = 0; c < 5; ++c) (void)r.cycle_once(kCycle);
  auto gone = r.master.readdress(1);
  ASSERT_FALSE(gone);
  EXPECT_EQ(gone.error(), master::MasterError::WorkingCounter);  // nothing at position 1
  ASSERT_TRUE(r.faults.clear(off));
  r.advance(kCycle);

  EXPECT_EQ(station_at(r, 1), 0u) << "power-up value of 0x0010";
  auto back = r.master.readdress(1);
  ASSERT_TRUE(back) << master::describe(back.error());
  EXPECT_TRUE(*back);
  EXPECT_EQ(station_at(r, 1), r.master.slave(1).station_address);
  EXPECT_EQ(r.master.slave(1).station_address, 0x1002);
  auto init = r.master.read_al_status(1);
  ASSERT_TRUE(init);
  EXPECT_TRUE(init->is(master::AlState::Init));

  // Configured again as at start-up, while the others keep cycling.
  ASSERT_TRUE(r.master.configure_mailbox(1));
  auto pre = r.master.request_state(1, master::AlState::PreOp);
  ASSERT_TRUE(pre && !pre->error());
  ASSERT_TRUE(r.master.write_process_data_config(1));
  auto safe = r.master.request_state(1, master::AlState::SafeOp);
  ASSERT_TRUE(safe && !safe->error()) << (safe ? safe->code : 0);
  for (int c = 0; c < 5; ++c) (void)r.cycle_once(kCycle);
  // The slave behind it lost its frames meanwhile: acknowledged, back to Op too.
  auto st2 = r.master.read_al_status(2);
  ASSERT_TRUE(st2);
  if (st2->error()) {
    ASSERT_TRUE(r.master.acknowledge_error(2));
  }
  for (std::size_t i : {1u, 2u}) {
    auto op = r.master.request_state(i, master::AlState::Op);
    ASSERT_TRUE(op && !op->error() && op->is(master::AlState::Op)) << i;
  }
  auto cyc = r.cycle_once(kCycle);
  ASSERT_TRUE(cyc);
  EXPECT_EQ(cyc->wkc, expected);
  EXPECT_TRUE(cyc->ok());
}

TEST(HotConnect, AnotherDeviceAtThePositionIsRefusedAndLeftWithoutAddress) {
  FaultRig r(2);
  ASSERT_EQ(r.bring_up(kCycle), "");
  const slave::FaultId off = r.engage("power_cycle", 1);
  ASSERT_TRUE(r.faults.clear(off));
  r.advance(kCycle);
  // As if another product had been plugged in: the scan's identity differs.
  r.master.slave(1).sii.product_code += 1;
  auto back = r.master.readdress(1);
  ASSERT_FALSE(back);
  EXPECT_EQ(back.error(), master::MasterError::WrongSlave);
  EXPECT_EQ(station_at(r, 1), 0u) << "the temporary address 0xFFFF is taken back";
}

}  // namespace
}  // namespace ecat::test
