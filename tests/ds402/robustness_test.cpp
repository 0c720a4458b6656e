// Hostile object values never crash, hang or produce NaN-driven garbage, and
// the cyclic path (drive step, binding copy, trace record) never allocates.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "ds402/motion_trace.hpp"
#include "harness.hpp"
#include "tests/support/alloc_counter.hpp"

namespace ecat::ds402::test {
namespace {

// Deterministic pseudo-random numbers (no std::random: same on every run).
struct Lcg {
  std::uint64_t s = 0x9E3779B97F4A7C15ull;
  std::uint32_t next() {
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<std::uint32_t>(s >> 32);
  }
  template <typename T>
  T any() {
    return static_cast<T>(next());
  }
};

TEST(Robustness, RandomObjectValuesKeepTheDriveSane) {
  Lcg rng;
  Harness h;
  for (int round = 0; round < 200; ++round) {
    DriveInputs& in = h.in;
    in.controlword = rng.any<std::uint16_t>();
    in.modes_of_operation = rng.any<std::int8_t>();
    in.target_position = rng.any<std::int32_t>();
    in.target_velocity = rng.any<std::int32_t>();
    in.target_torque = rng.any<std::int16_t>();
    in.position_offset = rng.any<std::int32_t>();
    in.velocity_offset = rng.any<std::int32_t>();
    in.torque_offset = rng.any<std::int16_t>();
    in.profile_velocity = rng.any<std::uint32_t>();
    in.profile_acceleration = rng.any<std::uint32_t>() % 4 ? rng.any<std::uint32_t>() : 0;
    in.profile_deceleration = rng.any<std::uint32_t>() % 4 ? rng.any<std::uint32_t>() : 0;
    in.quick_stop_deceleration = rng.any<std::uint32_t>() % 4 ? rng.any<std::uint32_t>() : 0;
    in.torque_slope = rng.any<std::uint32_t>();
    in.max_profile_velocity = rng.any<std::uint32_t>();
    in.max_motor_speed = rng.any<std::uint32_t>() % 10000;
    in.homing_method = rng.any<std::int8_t>();
    in.homing_speed_switch = rng.any<std::uint32_t>() % 1000000;
    in.homing_speed_zero = rng.any<std::uint32_t>() % 100000;
    in.homing_acceleration = rng.any<std::uint32_t>();
    in.home_offset = rng.any<std::int32_t>();
    in.software_limit_min = rng.any<std::int32_t>();
    in.software_limit_max = rng.any<std::int32_t>();
    in.max_torque = rng.any<std::uint16_t>();
    in.following_error_window = rng.any<std::uint32_t>();
    in.quick_stop_option = rng.any<std::int16_t>();
    in.shutdown_option = rng.any<std::int16_t>();
    in.disable_operation_option = rng.any<std::int16_t>();
    in.halt_option = rng.any<std::int16_t>();
    in.fault_reaction_option = rng.any<std::int16_t>();
    in.touch_probe_function = rng.any<std::uint16_t>();
    in.encoder_increments = rng.any<std::uint32_t>() % 3 ? 0 : rng.any<std::uint32_t>();
    in.motor_revolutions = rng.any<std::uint32_t>() % 3;
    in.gear_motor_revolutions = rng.any<std::uint32_t>() % 3;
    in.gear_shaft_revolutions = rng.any<std::uint32_t>() % 3;
    in.feed = rng.any<std::uint32_t>() % 2 ? 0 : rng.any<std::uint32_t>();
    in.feed_shaft_revolutions = rng.any<std::uint32_t>() % 3;
    in.sync_lost = rng.next() % 50 == 0;
    for (int i = 0; i < 20; ++i) {
      h.step();
      ASSERT_TRUE(std::isfinite(h.drive.plant().position()));
      ASSERT_TRUE(std::isfinite(h.drive.plant().velocity()));
    }
    // Recover: reset and enable with sane values must still work.
    if (round % 50 == 49) {
      h.in = DriveInputs{};
      h.command(0);
      h.command(0x80);
      h.command(0);
      h.run(500);
      h.enable(OperationMode::CyclicSyncVelocity);
      EXPECT_EQ(h.drive.state(), PdsState::OperationEnabled) << round;
    }
  }
  DriveOutputs out;
  h.drive.step(h.in, out, std::chrono::nanoseconds{0});  // zero-length cycle: no motion, no NaN
  EXPECT_TRUE(std::isfinite(h.drive.plant().position()));
}

TEST(Robustness, CyclicPathDoesNotAllocate) {
  Harness h;
  MotionTrace trace(5000);
  h.enable(OperationMode::ProfilePosition);
  h.in.target_position = 300000;
  h.in.touch_probe_function = 0x0031;
  ecat::test::AllocCounter counter;
  h.in.controlword = 0x001F;
  for (int i = 0; i < 2000; ++i) {
    h.step();
    trace.record(i * 0.001, h.in, h.out);
    if (i == 10) h.in.controlword = 0x000F;
    if (i == 1000) h.in.modes_of_operation = 8;
    if (i == 1500) h.drive.raise_fault(FaultKind::FollowingError);
  }
  EXPECT_EQ(counter.count(), 0u);
}

}  // namespace
}  // namespace ecat::ds402::test
