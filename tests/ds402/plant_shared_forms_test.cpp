// The plant's closed-form tables (Plant::ClosedForms) depend only on its
// parameters and the cycle length, so plants with equal inputs share one
// (issue 16 item 5: memory per drive). Sharing must change nothing: a plant
// whose inputs differ, or whose cycle length changes, gets its own table,
// and the plants still using the old one step exactly as a plant alone.
#include <gtest/gtest.h>

#include <vector>

#include "ds402/plant.hpp"
#include "harness.hpp"

namespace ecat::ds402::test {
namespace {

constexpr double kDt = 1e-3;
constexpr double kOtherDt = 0.5e-3;
constexpr int kCycles = 600;
constexpr int kSwitchAt = 200;  // the cycle from which plant b runs kOtherDt

// A velocity ramp up and down: turning, so the closed form is taken.
LoopDemand demand(int k) {
  LoopDemand d;
  d.kind = LoopDemand::Kind::Velocity;
  const double top = 200000.0;  // increments/s
  d.velocity = k < kCycles / 2 ? top * k / (kCycles / 2) : top * (kCycles - k) / (kCycles / 2);
  return d;
}

LoopLimits limits(const PlantParameters& p) {
  return LoopLimits{p.peak_torque, p.peak_torque, p.max_speed * p.encoder_resolution / 60.0};
}

struct State {
  double position, velocity, torque;
  bool operator==(const State&) const = default;
};

State state(const Plant& p) { return {p.position(), p.velocity(), p.torque()}; }

TEST(PlantSharedForms, PlantsOfEqualInputsShareOneTable) {
  const PlantParameters p;
  Plant a(p), b(p);
  EXPECT_EQ(a.closed_forms(), nullptr);
  for (int k = 0; k < 2; ++k) {  // built when the cycle length comes a second time
    a.step(demand(k), limits(p), kDt);
    b.step(demand(k), limits(p), kDt);
  }
  ASSERT_NE(a.closed_forms(), nullptr);
  EXPECT_EQ(a.closed_forms(), b.closed_forms());
  // Other parameters: another table.
  PlantParameters heavier = p;
  heavier.load_inertia *= 2;
  Plant c(heavier);
  c.step(demand(0), limits(heavier), kDt);
  c.step(demand(1), limits(heavier), kDt);
  ASSERT_NE(c.closed_forms(), nullptr);
  EXPECT_NE(c.closed_forms(), a.closed_forms());
  // A copy of a plant shares its table too.
  const Plant d = a;
  EXPECT_EQ(d.closed_forms(), a.closed_forms());
}

TEST(PlantSharedForms, AChangedCycleGetsItsOwnTableAndTheOtherIsUnaffected) {
  const PlantParameters p;
  // The reference: one plant alone, whose table nobody else holds.
  std::vector<State> alone;
  {
    Plant solo(p);
    for (int k = 0; k < kCycles; ++k) {
      solo.step(demand(k), limits(p), kDt);
      alone.push_back(state(solo));
    }
  }
  Plant a(p), b(p);
  Plant b_again(p);  // b's cycles once more, after b: it finds b's tables
  const void* table = nullptr;
  int closed = 0;
  for (int k = 0; k < kCycles; ++k) {
    a.step(demand(k), limits(p), kDt);
    b.step(demand(k), limits(p), k < kSwitchAt ? kDt : kOtherDt);
    if (a.last_path() == Plant::Path::ClosedForm) ++closed;
    ASSERT_EQ(state(a), alone[static_cast<std::size_t>(k)]) << "cycle " << k;
    if (k == 1) table = a.closed_forms();
    if (k >= 1) {
      ASSERT_EQ(a.closed_forms(), table) << "cycle " << k;
    }
    if (k >= kSwitchAt + 1) {
      ASSERT_NE(b.closed_forms(), nullptr);
      ASSERT_NE(b.closed_forms(), table) << "cycle " << k;
    } else if (k >= 1 && k < kSwitchAt) {
      ASSERT_EQ(b.closed_forms(), table) << "cycle " << k;
    }
  }
  EXPECT_GT(closed, kCycles / 2);  // the shared table was used
  // b's new table is shared in turn, and b steps as a plant of its cycles does.
  for (int k = 0; k < kCycles; ++k) b_again.step(demand(k), limits(p), k < kSwitchAt ? kDt : kOtherDt);
  EXPECT_EQ(state(b), state(b_again));
  EXPECT_EQ(b_again.closed_forms(), b.closed_forms());
}

// Drives of one description share their plant's table; a drive of another
// description has its own.
TEST(PlantSharedForms, DrivesOfOneDescriptionShareTheirPlantTable) {
  Harness one, two;
  PlantParameters other;
  other.rotor_inertia *= 1.5;
  Harness three(generic_drive(), other);
  one.run(3);
  two.run(3);
  three.run(3);
  ASSERT_NE(one.drive.plant().closed_forms(), nullptr);
  EXPECT_EQ(one.drive.plant().closed_forms(), two.drive.plant().closed_forms());
  ASSERT_NE(three.drive.plant().closed_forms(), nullptr);
  EXPECT_NE(three.drive.plant().closed_forms(), one.drive.plant().closed_forms());
}

}  // namespace
}  // namespace ecat::ds402::test
