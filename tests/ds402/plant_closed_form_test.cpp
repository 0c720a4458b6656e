// The plant's fast paths against its sub-step reference: Plant::step (rest
// point, closed form, sub-steps) and Plant::step_by_sub_steps, fed the same
// demands, must agree to rounding in every cycle, whatever the mode, limits,
// friction, load torque, parameters and cycle length; the rest point must
// agree exactly. Each scenario also checks that the fast paths were taken.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>

#include "ds402/plant.hpp"

namespace ecat::ds402::test {
namespace {

using Kind = LoopDemand::Kind;
using Path = Plant::Path;

struct Counts {
  int rest = 0, closed = 0, standstill = 0, sub = 0;
};

struct Scenario {
  std::string name;
  PlantParameters p;
  double dt = 1e-3;
  int cycles = 4000;
  // Demand, limits and load torque of cycle k.
  std::function<LoopDemand(int)> demand;
  std::function<LoopLimits(int, const PlantParameters&)> limits = [](int, const PlantParameters& pp) {
    return LoopLimits{pp.peak_torque, pp.peak_torque, pp.max_speed * pp.encoder_resolution / 60.0};
  };
  std::function<double(int)> load = [](int) { return 0.0; };
};

// Runs both plants side by side and compares them after every cycle.
void compare(const Scenario& s, Counts& c) {
  Plant fast(s.p), reference(s.p);
  const double rpm_scale = s.p.encoder_resolution / 60.0;  // increments/s per rpm
  for (int k = 0; k < s.cycles; ++k) {
    const LoopDemand d = s.demand(k);
    const LoopLimits lim = s.limits(k, s.p);
    fast.set_external_torque(s.load(k));
    reference.set_external_torque(s.load(k));
    fast.step(d, lim, s.dt);
    reference.step_by_sub_steps(d, lim, s.dt);
    switch (fast.last_path()) {
      case Path::Rest:
        ++c.rest;
        // From the same state, exactly what the sub-steps leave.
        if (c.rest == k + 1) {
          EXPECT_EQ(fast.position(), reference.position()) << s.name << " cycle " << k;
          EXPECT_EQ(fast.torque(), reference.torque()) << s.name << " cycle " << k;
        }
        break;
      case Path::ClosedForm: ++c.closed; break;
      case Path::Standstill: ++c.standstill; break;
      case Path::SubSteps: ++c.sub; break;
    }
    const std::string at = s.name + " cycle " + std::to_string(k);
    ASSERT_NEAR(fast.position(), reference.position(), 1e-6 + 1e-12 * std::abs(reference.position())) << at;
    ASSERT_NEAR(fast.velocity(), reference.velocity(), 1e-6 * rpm_scale) << at;  // 1e-6 rpm
    ASSERT_NEAR(fast.torque(), reference.torque(), 1e-10) << at;
    ASSERT_NEAR(fast.torque_command(), reference.torque_command(), 1e-10) << at;
    ASSERT_EQ(fast.torque_limited(), reference.torque_limited()) << at;
  }
}

Counts run(const Scenario& s) {
  Counts c;
  compare(s, c);
  return c;
}

// A back-and-forth trapezoid set-point of `top` increments/s at time t (s):
// 0.1 s ramps, 0.8 s at speed, then the way back.
double trapezoid(double t, double top, double* velocity = nullptr) {
  constexpr double kRamp = 0.1, kCruise = 0.8, kLeg = 2 * kRamp + kCruise;
  const double acc = top / kRamp;
  auto leg = [&](double u, double& v) {  // position u seconds into one leg
    if (u <= kRamp) {
      v = acc * u;
      return acc * u * u / 2;
    }
    if (u <= kRamp + kCruise) {
      v = top;
      return acc * kRamp * kRamp / 2 + top * (u - kRamp);
    }
    const double d = u - kRamp - kCruise;
    v = top - acc * d;
    return acc * kRamp * kRamp / 2 + top * kCruise + top * d - acc * d * d / 2;
  };
  const double in_period = std::fmod(t, 2 * kLeg);
  double v = 0, v_end = 0;
  double pos;
  if (in_period < kLeg) {
    pos = leg(in_period, v);
  } else {
    pos = leg(kLeg, v_end) - leg(in_period - kLeg, v);
    v = -v;
  }
  if (velocity) *velocity = v;
  return pos;
}

TEST(PlantClosedForm, CspMoveMatchesTheSubSteps) {
  Scenario s;
  s.name = "csp move";
  s.demand = [](int k) {
    double v = 0;
    const double x = std::round(trapezoid(k * 1e-3, 2.0e6, &v));
    return LoopDemand{Kind::Position, x, v, 0, 0};
  };
  const Counts c = run(s);
  EXPECT_GT(c.closed, s.cycles / 2);  // cruising is linear
  EXPECT_GT(c.sub, 0);                // starting from rest and reversing are not
}

TEST(PlantClosedForm, FeedForwardOffsetsAndOtherCycleTimes) {
  for (const double dt : {1e-3, 250e-6, 2e-3, 125e-6, 62.5e-6}) {
    Scenario s;
  s.name = "feed-forward dt " + std::to_string(dt);
    s.p.velocity_feed_forward = 0.7;
    s.p.sub_step = 1e-4;  // 1 ms: 10 sub-steps
    s.dt = dt;
    s.cycles = static_cast<int>(4.0 / dt);
    s.demand = [dt](int k) {
      double v = 0;
      const double x = trapezoid((k + 1) * dt, 1.0e6, &v);
      return LoopDemand{Kind::Position, x, v, 0.05, 3000};
    };
    s.load = [dt](int k) { return (k * dt > 1.5 && k * dt < 2.5) ? 0.3 : 0.0; };  // a load torque for a second
    const Counts c = run(s);
    EXPECT_GT(c.closed, s.cycles / 4) << s.name;
  }
}

TEST(PlantClosedForm, VelocityModeAndTorqueLimit) {
  Scenario s;
  s.name = "velocity";
  s.demand = [](int k) {
    const double v = k < 1000 ? 500000.0 : (k < 2000 ? -800000.0 : (k < 3000 ? 3.0e6 : 0.0));
    return LoopDemand{Kind::Velocity, 0, v, 0, k < 1500 ? 0.0 : 1000.0};
  };
  // A low torque limit for a while: the steps to a new speed saturate.
  s.limits = [](int k, const PlantParameters& p) {
    const double t = (k > 500 && k < 2500) ? 0.4 : p.peak_torque;
    return LoopLimits{t, t * 0.5, 4000 * p.encoder_resolution / 60.0};
  };
  const Counts c = run(s);
  EXPECT_GT(c.closed, s.cycles / 2);
  EXPECT_GT(c.sub, 10);
}

TEST(PlantClosedForm, VelocityLimitClampsTheCommand) {
  Scenario s;
  s.name = "velocity limit";
  s.demand = [](int k) {
    double v = 0;
    const double x = trapezoid(k * 1e-3, 2.5e6, &v);
    return LoopDemand{Kind::Position, x, v, 0, 0};
  };
  s.limits = [](int, const PlantParameters& p) {
    return LoopLimits{p.peak_torque, p.peak_torque, 1000 * p.encoder_resolution / 60.0};  // below the demand
  };
  run(s);
}

TEST(PlantClosedForm, TorqueModeOffAndRest) {
  Scenario s;
  s.name = "torque, off, rest";
  s.cycles = 6000;
  s.demand = [](int k) {
    if (k < 500) return LoopDemand{Kind::Off, 0, 0, 0, 0};  // a new plant, switched off: at rest
    if (k < 700) return LoopDemand{Kind::Torque, 0, 0, 0.05, 0};
    if (k < 2000) return LoopDemand{Kind::Off, 0, 0, 0, 0};  // coasts to a stop
    if (k < 3000) return LoopDemand{Kind::Torque, 0, 0, 0.01, 0};  // below Coulomb friction: stands
    if (k < 4000) return LoopDemand{Kind::Position, 5000, 0, 0, 0};
    return LoopDemand{Kind::Velocity, 0, 0, 0, 0};
  };
  const Counts c = run(s);
  EXPECT_GE(c.rest, 500);  // and again once the torque has decayed to exactly 0 after the stop
  EXPECT_GT(c.standstill, 1000);  // torque below friction, holding, velocity 0 after the stop
}

TEST(PlantClosedForm, MoveThenHold) {
  Scenario s;
  s.name = "move, then hold where it stopped";
  s.cycles = 3000;
  s.demand = [](int k) {  // 0.2 s of a 2e7 inc/s² triangle, then standing still
    const double t = std::min(k + 1, 200) * 1e-3;
    const double x = t < 0.1 ? 1e7 * t * t : 1e5 - 1e7 * (0.2 - t) * (0.2 - t);
    const double v = t < 0.1 ? 2e7 * t : 2e7 * (0.2 - t);
    return LoopDemand{Kind::Position, std::round(x), v, 0, 0};
  };
  const Counts c = run(s);
  EXPECT_GT(c.standstill, 2000);  // held by friction with the integral slowly unwinding
  EXPECT_GT(c.closed, 50);        // the decay towards the target
}

// A cycle time that jitters (free-running loop on the real clock): the
// closed-form matrices are not rebuilt each cycle, the sub-steps run, and a
// steady cycle time brings the closed form back from its second cycle.
TEST(PlantClosedForm, JitteringCycleTimeRunsTheSubSteps) {
  const PlantParameters p;
  Plant fast(p), reference(p);
  const LoopLimits lim{p.peak_torque, p.peak_torque, p.max_speed * p.encoder_resolution / 60.0};
  double t = 0;
  for (int k = 0; k < 2000; ++k) {
    const bool jitter = k < 1000;
    const double dt = jitter ? 1e-3 + ((k * 7919) % 201 - 100) * 1e-8 : 1e-3;  // +-1 us
    t += dt;
    double v = 0;
    const double x = std::round(trapezoid(t, 1.0e6, &v));
    const LoopDemand d{Kind::Position, x, v, 0, 0};
    fast.step(d, lim, dt);
    reference.step_by_sub_steps(d, lim, dt);
    if (jitter && k > 0) {
      ASSERT_NE(fast.last_path(), Path::ClosedForm) << k;
    }
    if (k == 1001) {
      EXPECT_EQ(fast.last_path(), Path::ClosedForm);  // 1 ms twice in a row, at speed
    }
    ASSERT_NEAR(fast.position(), reference.position(), 1e-6 + 1e-12 * std::abs(reference.position())) << k;
    ASSERT_NEAR(fast.velocity(), reference.velocity(), 1e-4) << k;
  }
}

TEST(PlantClosedForm, HoldingWhereItStandsIsTheRestPoint) {
  PlantParameters p;
  p.initial_position = 123456;
  Plant fast(p), reference(p);
  const LoopLimits lim{p.peak_torque, p.peak_torque, 1e7};
  const LoopDemand hold{Kind::Position, 123456, 0, 0, 0};
  for (int k = 0; k < 100; ++k) {
    fast.step(hold, lim, 1e-3);
    reference.step_by_sub_steps(hold, lim, 1e-3);
    ASSERT_EQ(fast.last_path(), Path::Rest);
    ASSERT_EQ(fast.position(), reference.position());
    ASSERT_EQ(fast.velocity(), reference.velocity());
    ASSERT_EQ(fast.torque(), reference.torque());
    ASSERT_EQ(fast.torque_command(), reference.torque_command());
  }
  // A load torque above the friction is no rest point: the rotor moves.
  fast.set_external_torque(0.5);
  fast.step(hold, lim, 1e-3);
  EXPECT_EQ(fast.last_path(), Path::SubSteps);
  EXPECT_LT(fast.position(), 123456);
  // Nor is a reference one increment away: the controller acts, friction
  // holds the rotor for a while, then it breaks away.
  Plant other(p), other_reference(p);
  const LoopDemand near{Kind::Position, 123457, 0, 0, 0};
  other.step(near, lim, 1e-3);
  other_reference.step_by_sub_steps(near, lim, 1e-3);
  EXPECT_EQ(other.last_path(), Path::Standstill);
  EXPECT_GT(other.torque_command(), 0);
  EXPECT_NEAR(other.torque_command(), other_reference.torque_command(), 1e-12);
  EXPECT_NEAR(other.torque(), other_reference.torque(), 1e-12);
  EXPECT_EQ(other.position(), 123456);
}

}  // namespace
}  // namespace ecat::ds402::test

namespace ecat::ds402::test {
namespace {

// Deterministic pseudo-random numbers (no std::random: same on every run).
struct Lcg {
  std::uint64_t s = 0x2545F4914F6CDD1Dull;
  double uniform(double lo, double hi) {
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return lo + (hi - lo) * static_cast<double>(s >> 11) / 9007199254740992.0;
  }
  int below(int n) { return static_cast<int>(uniform(0, n)); }
};

// Random plants, demands, limits and loads; before every cycle the plant
// under test is a copy of the reference, so each step is compared from the
// same state (differences cannot accumulate) with tight tolerances.
TEST(PlantClosedForm, RandomisedSingleStepsAgree) {
  Lcg rng;
  Counts c;
  for (int plant_no = 0; plant_no < 40; ++plant_no) {
    PlantParameters p;
    p.rotor_inertia = rng.uniform(1e-5, 1e-3);
    p.load_inertia = rng.uniform(0, 5e-3);
    p.viscous_friction = rng.uniform(0, 1e-3);
    p.coulomb_friction = rng.below(4) == 0 ? 0.0 : rng.uniform(0, 0.2);
    p.peak_torque = rng.uniform(0.5, 20);
    p.velocity_bandwidth = rng.uniform(20, 300);
    p.position_gain = rng.uniform(10, 300);
    p.velocity_feed_forward = rng.below(2) ? 0.0 : rng.uniform(0, 1);
    p.current_time_constant = rng.uniform(5e-5, 1e-3);
    p.sub_step = rng.uniform(3e-5, 1.25e-4);
    const double dt = std::array<double, 4>{1e-3, 5e-4, 2e-3, 250e-6}[static_cast<std::size_t>(rng.below(4))];
    Plant reference(p);
    double target = 0, velocity = 0;
    Kind kind = Kind::Position;
    LoopLimits lim{p.peak_torque, p.peak_torque, p.max_speed * p.encoder_resolution / 60.0};
    double load = 0, torque_ff = 0, velocity_offset = 0;
    for (int k = 0; k < 1500; ++k) {
      if (rng.below(200) == 0) kind = static_cast<Kind>(rng.below(4));
      if (rng.below(100) == 0) velocity = rng.below(3) == 0 ? 0.0 : rng.uniform(-3e6, 3e6);  // a new speed
      if (rng.below(300) == 0) lim.torque_positive = rng.below(2) ? p.peak_torque : rng.uniform(0, p.peak_torque);
      if (rng.below(300) == 0) lim.torque_negative = rng.below(2) ? p.peak_torque : rng.uniform(0, p.peak_torque);
      if (rng.below(300) == 0) lim.velocity = rng.uniform(1e5, 1e7);
      if (rng.below(300) == 0) load = rng.below(2) ? 0.0 : rng.uniform(-0.5, 0.5);
      if (rng.below(300) == 0) torque_ff = rng.below(2) ? 0.0 : rng.uniform(-0.3, 0.3);
      if (rng.below(300) == 0) velocity_offset = rng.below(2) ? 0.0 : rng.uniform(-1e4, 1e4);
      target = std::round(target + velocity * dt);
      const double torque = kind == Kind::Torque ? rng.uniform(-0.5, 0.5) * (rng.below(20) == 0) + torque_ff : torque_ff;
      const LoopDemand d{kind, target, velocity, torque, velocity_offset};
      Plant fast = reference;
      const double v_start = reference.velocity(), t_start = reference.torque();
      fast.set_external_torque(load);
      reference.set_external_torque(load);
      fast.step(d, lim, dt);
      reference.step_by_sub_steps(d, lim, dt);
      switch (fast.last_path()) {
        case Path::Rest: ++c.rest; break;
        case Path::ClosedForm: ++c.closed; break;
        case Path::Standstill: ++c.standstill; break;
        case Path::SubSteps: ++c.sub; break;
      }
      const std::string at = "plant " + std::to_string(plant_no) + " cycle " + std::to_string(k);
      // Rounding is relative to the magnitudes combined: start and end values.
      // The position itself is known to its ulp only (1.5e-11 at 1e5
      // increments), in both paths; the position loop turns that into a
      // velocity command of position_gain times it each sub-step.
      const int n = static_cast<int>(std::ceil(dt / p.sub_step - 1e-9));
      const double v_tolerance =
          1e-9 * (std::abs(reference.velocity()) + std::abs(v_start) + std::abs(velocity) + 1.0) +
          16 * 2.2e-16 * p.position_gain * n * std::abs(reference.position());
      const double t_scale = std::abs(reference.torque()) + std::abs(t_start) + 1e-3;
      ASSERT_NEAR(fast.position(), reference.position(), 1e-7 + 1e-12 * std::abs(reference.position())) << at;
      ASSERT_NEAR(fast.velocity(), reference.velocity(), v_tolerance) << at;
      ASSERT_NEAR(fast.torque(), reference.torque(), 1e-9 * t_scale) << at;
      ASSERT_NEAR(fast.torque_command(), reference.torque_command(), 1e-9 * t_scale) << at;
      ASSERT_EQ(fast.torque_limited(), reference.torque_limited()) << at;
      if (std::abs(reference.position()) > 1e12) break;  // ran away (torque mode): enough of this plant
    }
  }
  EXPECT_GT(c.closed, 5000);
  EXPECT_GT(c.standstill, 1000);
  EXPECT_GT(c.sub, 1000);
  std::printf("paths: rest %d, closed form %d, standstill %d, sub-steps %d\n", c.rest, c.closed, c.standstill, c.sub);
}

}  // namespace
}  // namespace ecat::ds402::test
