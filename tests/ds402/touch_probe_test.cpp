// Touch probe 60B8h-60BDh: latches on the probe input edges or the index
// pulse, single and continuous trigger.
#include <gtest/gtest.h>

#include "ds402/controlword.hpp"
#include "ds402/statusword.hpp"
#include "ds402/touch_probe.hpp"
#include "harness.hpp"

namespace ecat::ds402::test {
namespace {

constexpr std::uint16_t kEnableOp = 0x000F;

PlantParameters probes() {
  PlantParameters p;
  p.probe1_low = 700000;
  p.probe1_high = 800000;
  return p;
}

struct Probe : ::testing::Test {
  Harness h{generic_drive(), probes()};
  void SetUp() override {
    h.in.profile_velocity = 400000;
    h.in.profile_acceleration = 4000000;
    h.in.profile_deceleration = 4000000;
    h.enable(OperationMode::ProfilePosition);
  }
  void move_to(std::int32_t target) {
    h.in.target_position = target;
    h.command(kEnableOp | cw::kNewSetPoint);
    h.command(kEnableOp);
    ASSERT_GT(h.run_until([&] { return h.bit(sw::kTargetReached); }, 20000), 0);
  }
};

// Probe 1 input is active over [700000, 800000].
TEST_F(Probe, SingleTriggerOnBothEdgesOfTheInput) {
  h.in.touch_probe_function = tp::kEnable | tp::kPositiveEdge | tp::kNegativeEdge;
  h.step();
  EXPECT_EQ(h.out.touch_probe_status, tp::kEnabled);
  move_to(900000);
  EXPECT_EQ(h.out.touch_probe_status, tp::kEnabled | tp::kPositiveStored | tp::kNegativeStored);
  EXPECT_EQ(h.out.touch_probe_1_positive, 700000);
  EXPECT_EQ(h.out.touch_probe_1_negative, 800000);
  // Back through the mark: single trigger keeps the first values.
  move_to(0);
  EXPECT_EQ(h.out.touch_probe_1_positive, 700000);
  EXPECT_EQ(h.out.touch_probe_1_negative, 800000);
  // Re-arming the positive edge (bit 4 off and on) takes the next one: on the
  // way back down, the input goes active at 800000.
  h.in.touch_probe_function = tp::kEnable | tp::kNegativeEdge;
  h.step();
  EXPECT_EQ(h.out.touch_probe_status, tp::kEnabled | tp::kNegativeStored);
  h.in.touch_probe_function = tp::kEnable | tp::kPositiveEdge | tp::kNegativeEdge;
  move_to(900000);
  EXPECT_EQ(h.out.touch_probe_1_positive, 700000);
  move_to(0);
  EXPECT_EQ(h.out.touch_probe_1_positive, 700000);  // stored again after the first move up
}

TEST_F(Probe, ContinuousTriggerTogglesOnEveryValue) {
  h.in.touch_probe_function = tp::kEnable | tp::kContinuous | tp::kPositiveEdge;
  h.step();
  move_to(900000);
  EXPECT_EQ(h.out.touch_probe_1_positive, 700000);
  EXPECT_EQ(h.out.touch_probe_status, tp::kEnabled | tp::kPositiveStored | tp::kPositiveToggle);
  move_to(0);  // entering from above: rising edge at 800000
  EXPECT_EQ(h.out.touch_probe_1_positive, 800000);
  EXPECT_EQ(h.out.touch_probe_status, tp::kEnabled | tp::kPositiveStored);
}

TEST_F(Probe, Probe2OnTheIndexPulse) {
  // Probe 2, trigger = index pulse (bits 10/11 = 01), positive edge.
  h.in.touch_probe_function = static_cast<std::uint16_t>((tp::kEnable | tp::kTriggerIndex | tp::kPositiveEdge)
                                                         << tp::kProbe2Shift);
  h.step();
  move_to(200000);
  EXPECT_EQ(h.out.touch_probe_status, (tp::kEnabled | tp::kPositiveStored) << tp::kProbe2Shift);
  EXPECT_EQ(h.out.touch_probe_2_positive, 1000);  // first index pulse at 0*131072 + 1000
}

TEST_F(Probe, DisabledProbeReportsNothing) {
  move_to(900000);
  EXPECT_EQ(h.out.touch_probe_status, 0);
  EXPECT_EQ(h.out.touch_probe_1_positive, 0);
  EXPECT_EQ(h.out.digital_inputs, 0u);
  move_to(750000);
  EXPECT_EQ(h.out.digital_inputs, 1u << 16);  // probe 1 input
}

}  // namespace
}  // namespace ecat::ds402::test
