// The drive-terminal faults of slave::FaultCatalogue (docs/faults.md
// "Drive"): a limit switch, the quick-stop input, safe torque off and a
// stuck holding brake, on a generic servo in CSP with the project's master
// over the in-process wire. The statusword, 603Fh and 6077h come from the
// process image the master reads (1A00h: 6041h @0, 6064h @2, 606Ch @6,
// 6077h @10, 6061h @12, 603Fh @14); 60FDh, 1001h and 605Ah over SDO.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <vector>
#include <string>
#include <utility>

#include "common/le.hpp"
#include "master/coe_client.hpp"
#include "tests/slave/fault_rig.hpp"

namespace ecat::test {
namespace {

constexpr Nanoseconds kCycle = std::chrono::milliseconds(1);
constexpr std::uint16_t kDigitalInputs = 0x60FD, kErrorRegister = 0x1001, kQuickStopOption = 0x605A;
constexpr std::uint16_t kFollowingErrorWindow = 0x6065, kFollowingErrorTimeout = 0x6066;
constexpr std::int8_t kCsp = 8;
// Statusword values (CiA 402-2 Table 32, with bit 4 voltage enabled and bit 9 remote).
constexpr std::uint16_t kStateMask = 0x006F;
constexpr std::uint16_t kSwitchOnDisabled = 0x0040, kOperationEnabled = 0x0027, kQuickStopActive = 0x0007,
                        kFault = 0x0008;
constexpr std::uint16_t kInternalLimit = 1u << 11;

// One generic servo in Op, CSP, with the outputs 1600h: 6040h @0, 607Ah @2,
// 60FFh @6, 6071h @10, 6060h @12.
struct DriveRig : FaultRig {
  std::int32_t target = 0;

  DriveRig() : FaultRig(1) {}
  void command(std::uint16_t cw) { store_le(master.outputs(0).data(), cw); }
  void set_target(std::int32_t p) {
    target = p;
    store_le(master.outputs(0).data() + 2, static_cast<std::uint32_t>(p));
  }
  void mode(std::int8_t m) { master.outputs(0)[12] = static_cast<std::uint8_t>(m); }
  std::uint16_t statusword() const { return load_le<std::uint16_t>(master.inputs(0).data()); }
  std::int32_t position() const { return static_cast<std::int32_t>(load_le<std::uint32_t>(master.inputs(0).data() + 2)); }
  std::int16_t torque() const { return static_cast<std::int16_t>(load_le<std::uint16_t>(master.inputs(0).data() + 10)); }
  std::uint16_t error_code() const { return load_le<std::uint16_t>(master.inputs(0).data() + 14); }
  void cycles(int n, std::int32_t step = 0) {
    for (int i = 0; i < n; ++i) {
      if (step != 0) set_target(target + step);
      ASSERT_TRUE(cycle_once(kCycle));
    }
  }
  // Shutdown, switch on, enable operation: Operation enabled in CSP at rest.
  void enable() {
    mode(kCsp);
    set_target(position());
    command(0x0006);
    cycles(3);
    command(0x0007);
    cycles(3);
    command(0x000F);
    cycles(3);
    ASSERT_EQ(statusword() & kStateMask, kOperationEnabled) << std::hex << statusword();
  }
};

// Through one CoeClient per test: it keeps the emergencies it reads.
std::uint32_t upload(master::CoeClient& coe, std::uint16_t index, std::uint8_t sub = 0) {
  auto v = coe.upload_value(index, sub);
  EXPECT_TRUE(v) << std::hex << index;
  return v ? *v : 0xDEADBEEF;
}
void download(master::CoeClient& coe, std::uint16_t index, std::uint32_t value, std::size_t bytes,
              std::uint8_t sub = 0) {
  EXPECT_TRUE(coe.download_value(index, sub, value, bytes)) << std::hex << index;
}

TEST(FaultDrive, LimitSwitch) {
  DriveRig r;
  ASSERT_EQ(r.bring_up(kCycle), "");
  master::CoeClient coe(r.master, 0);
  r.cycles(2);
  r.enable();
  const std::uint16_t enabled = r.statusword();
  EXPECT_EQ(upload(coe, kDigitalInputs), 0u);

  const slave::FaultId id = r.engage("limit_switch", 0, {{"side", 1}});
  r.cycles(2);
  // The input shows, statusword bit 11, still enabled, no fault.
  EXPECT_EQ(upload(coe, kDigitalInputs), 0x00000002u);
  EXPECT_EQ(r.statusword(), enabled | kInternalLimit);
  EXPECT_EQ(r.error_code(), 0);
  // Moving away from it (negative) is allowed.
  r.cycles(20, -200);
  EXPECT_EQ(r.statusword() & kStateMask, kOperationEnabled);
  EXPECT_EQ(r.error_code(), 0);
  // Moving into it: the limit-switch fault FF03h, its EMCY, 1001h generic + manufacturer.
  r.cycles(20, 200);
  // Fault 0x0008 | voltage 0x0010 | remote 0x0200 | internal limit 0x0800 (the input is still active).
  EXPECT_EQ(r.statusword(), 0x0A18);
  EXPECT_EQ(r.error_code(), 0xFF03);
  EXPECT_EQ(upload(coe, kErrorRegister), 0x81u);
  (void)coe.upload_value(kErrorRegister, 0);  // reads the queued EMCY too
  ASSERT_FALSE(coe.emergencies().empty());
  EXPECT_EQ(coe.emergencies().back().error_code, 0xFF03);

  ASSERT_TRUE(r.faults.clear(id));
  r.command(0x0080);
  r.cycles(3);
  EXPECT_EQ(upload(coe, kDigitalInputs), 0u);
  EXPECT_EQ(r.statusword() & kStateMask, kSwitchOnDisabled);
  EXPECT_EQ(r.error_code(), 0);
}

TEST(FaultDrive, QuickStopInputRampsThenSwitchOnDisabled) {
  DriveRig r;
  ASSERT_EQ(r.bring_up(kCycle), "");
  master::CoeClient coe(r.master, 0);
  r.cycles(2);
  r.enable();
  EXPECT_EQ(upload(coe, kQuickStopOption), 2u);  // 605Ah default: quick-stop ramp, then Switch on disabled
  r.cycles(50, 1000);                          // moving at 1 000 000 inc/s
  const slave::FaultId id = r.engage("quick_stop_input", 0);
  r.set_target(r.position());
  std::vector<std::uint16_t> sw;
  for (int i = 0; i < 150; ++i) {
    r.cycles(1);
    sw.push_back(r.statusword());
  }
  // Quick stop active (x00x 0111 | voltage | remote = 0x0217): for the first
  // two cycles the ramp's start is at the torque limit (bit 11); at rest,
  // target reached (bit 10, 0x0617) for one cycle; then transition 12 to
  // Switch on disabled (0x0250).
  EXPECT_EQ(sw[0] & kStateMask, kQuickStopActive);
  std::vector<std::pair<std::size_t, std::uint16_t>> changes{{0, sw[0]}};
  for (std::size_t i = 1; i < sw.size(); ++i) {
    if (sw[i] != sw[i - 1]) changes.emplace_back(i, sw[i]);
  }
  EXPECT_EQ(changes, (std::vector<std::pair<std::size_t, std::uint16_t>>{
                         {0, 0x0A17}, {2, 0x0217}, {140, 0x0617}, {141, 0x0250}}));
  EXPECT_EQ(r.error_code(), 0);
  // The master's enable sequence is refused while the input is active.
  r.command(0x0006);
  r.cycles(3);
  r.command(0x000F);
  r.cycles(3);
  EXPECT_EQ(r.statusword() & kStateMask, kSwitchOnDisabled);
  ASSERT_TRUE(r.faults.clear(id));
  r.enable();
}

// 605Ah = 6 (quick-stop ramp, stay in Quick stop active): the drive stops
// and stays there while the input is active; cleared, the master's enable
// operation (0x0F) takes transition 16 back to Operation enabled.
TEST(FaultDrive, QuickStopInputStaysInQuickStopActiveWithOption6) {
  DriveRig r;
  ASSERT_EQ(r.bring_up(kCycle), "");
  master::CoeClient coe(r.master, 0);
  download(coe, kQuickStopOption, 6, 2);
  r.cycles(2);
  r.enable();
  r.cycles(50, 1000);
  const slave::FaultId id = r.engage("quick_stop_input", 0);
  r.set_target(r.position());
  r.cycles(200);
  EXPECT_EQ(r.statusword(), 0x0617);  // Quick stop active, at rest (target reached)
  EXPECT_EQ(r.error_code(), 0);
  ASSERT_TRUE(r.faults.clear(id));
  r.set_target(r.position());
  r.cycles(3);
  EXPECT_EQ(r.statusword() & kStateMask, kOperationEnabled);
}

TEST(FaultDrive, SafeTorqueOff) {
  DriveRig r;
  ASSERT_EQ(r.bring_up(kCycle), "");
  master::CoeClient coe(r.master, 0);
  r.cycles(2);
  r.enable();
  r.cycles(50, 1000);
  const slave::FaultId id = r.engage("sto", 0);
  r.cycles(1, 1000);
  // At once: Fault reaction active (0x021F) with no torque, 603Fh = 5441h.
  EXPECT_EQ(r.statusword(), 0x021F);
  EXPECT_EQ(r.error_code(), 0x5441);
  EXPECT_EQ(r.torque(), 0);
  r.cycles(2, 1000);
  EXPECT_EQ(r.statusword(), 0x0218);  // Fault
  EXPECT_EQ(r.error_code(), 0x5441);
  EXPECT_EQ(r.torque(), 0);
  EXPECT_EQ(upload(coe, kErrorRegister), 0x21u);  // generic + device profile
  (void)coe.upload_value(kErrorRegister, 0);
  ASSERT_FALSE(coe.emergencies().empty());
  EXPECT_EQ(coe.emergencies().back().error_code, 0x5441);
  EXPECT_EQ(coe.emergencies().back().error_register, 0x21);
  const std::size_t emcys = coe.emergencies().size();
  // Fault reset while STO is active: refused, still Fault, no new EMCY.
  r.command(0x0080);
  r.cycles(3);
  EXPECT_EQ(r.statusword() & kStateMask, kFault);
  EXPECT_EQ(r.error_code(), 0x5441);
  (void)coe.upload_value(kErrorRegister, 0);
  EXPECT_EQ(coe.emergencies().size(), emcys);

  ASSERT_TRUE(r.faults.clear(id));
  r.command(0x0000);
  r.cycles(2);
  r.command(0x0080);
  r.cycles(3);
  EXPECT_EQ(r.statusword() & kStateMask, kSwitchOnDisabled);
  EXPECT_EQ(r.error_code(), 0);
  (void)coe.upload_value(kErrorRegister, 0);
  ASSERT_GT(coe.emergencies().size(), emcys);
  EXPECT_EQ(coe.emergencies().back().error_code, 0x0000);
}

TEST(FaultDrive, BrakeStuck) {
  DriveRig r;
  ASSERT_EQ(r.bring_up(kCycle), "");
  master::CoeClient coe(r.master, 0);
  download(coe, kFollowingErrorWindow, 10000, 4);  // 6065h: 10 000 increments
  download(coe, kFollowingErrorTimeout, 10, 2);    // 6066h: 10 ms
  r.cycles(2);
  r.enable();
  const slave::FaultId id = r.engage("brake_stuck", 0);
  // At standstill nothing happens.
  r.cycles(100);
  EXPECT_EQ(r.statusword() & kStateMask, kOperationEnabled);
  EXPECT_EQ(r.error_code(), 0);
  const std::int32_t held = r.position();
  // Under motion the rotor stays put: the following error passes 6065h and
  // the drive faults with 8611h.
  int cycles = 0;
  while (cycles < 200 && (r.statusword() & kStateMask) != kFault) {
    r.cycles(1, 1000);
    ++cycles;
  }
  // 1000 inc per cycle: 6065h (10 000) passed after 10 cycles, held 6066h
  // (10 ms) more, the fault in the cycle after.
  EXPECT_EQ(cycles, 23);
  EXPECT_EQ(r.statusword(), 0x0218);
  EXPECT_EQ(r.error_code(), 0x8611);
  EXPECT_EQ(r.position(), held);
  (void)coe.upload_value(kErrorRegister, 0);
  ASSERT_FALSE(coe.emergencies().empty());
  EXPECT_EQ(coe.emergencies().back().error_code, 0x8611);
  ASSERT_TRUE(r.faults.clear(id));
}

TEST(FaultDrive, RefusesBadRequests) {
  DriveRig r;
  const std::pair<slave::FaultRequest, std::string> bad[] = {
      {{"limit_switch", 0, std::nullopt, {}}, "limit_switch: parameter 'side' is required"},
      {{"limit_switch", 0, std::nullopt, {{"side", 2}}}, "limit_switch: side = 2 is out of range"},
      {{"sto", 0, std::nullopt, {{"axis", 1}}}, "sto: slave 0 runs no CiA 402 drive with an axis 1"},
      {{"brake_stuck", std::nullopt, std::nullopt, {}}, "brake_stuck: needs a slave"},
      {{"quick_stop_input", 0, 1, {}}, "quick_stop_input: takes no port"},
  };
  r.expect_refused(bad);
  const slave::FaultId id = r.engage("sto", 0);
  auto again = r.faults.engage({"sto", 0, std::nullopt, {}});
  ASSERT_FALSE(again);
  EXPECT_EQ(again.error(), "sto: that input of the drive is already forced");
  auto cycle = r.faults.engage({"power_cycle", 0, std::nullopt, {}});
  ASSERT_FALSE(cycle);
  ASSERT_TRUE(r.faults.clear(id));
}

}  // namespace
}  // namespace ecat::test
