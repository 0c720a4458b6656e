// The whole stack in one process: master library -> in-memory wire -> ESC
// -> ESM/CoE firmware -> CiA402 drive and plant, on simulated time.
#include <gtest/gtest.h>

#include <cstdlib>

#include "common/le.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

// Generic servo default PDOs (xml/devices/generic-servo.xml): 1600h and 1A00h.
constexpr std::size_t kControlword = 0, kTargetPosition = 2, kModes = 12;
constexpr std::size_t kStatusword = 0, kActualPosition = 2;
constexpr std::uint16_t kGenericOutputBytes = 14, kGenericInputBytes = 16;
constexpr std::uint16_t kWkcOneDrive = 3;  // LRW: outputs +2, inputs +1
constexpr Nanoseconds kCycle = std::chrono::milliseconds(1);

std::uint16_t statusword(InProcess& p) { return load_le<std::uint16_t>(p.master.inputs(0).data() + kStatusword); }
std::int32_t actual(InProcess& p) {
  return static_cast<std::int32_t>(load_le<std::uint32_t>(p.master.inputs(0).data() + kActualPosition));
}
void command(InProcess& p, std::uint16_t cw, std::int32_t target) {
  std::uint8_t* out = p.master.outputs(0).data();
  store_le<std::uint16_t>(out + kControlword, cw);
  store_le<std::uint32_t>(out + kTargetPosition, static_cast<std::uint32_t>(target));
  out[kModes] = 8;  // cyclic synchronous position
}

TEST(InProcessStack, GenericServoReachesOpWithItsDefaultPdos) {
  InProcess p;
  p.add_default();
  ASSERT_EQ(p.bring_up(), "");
  EXPECT_EQ(p.master.slave(0).pd.output_bytes, kGenericOutputBytes);
  EXPECT_EQ(p.master.slave(0).pd.input_bytes, kGenericInputBytes);
  EXPECT_EQ(p.master.expected_wkc(), kWkcOneDrive);
  auto st = p.master.read_al_status(0);
  ASSERT_TRUE(st);
  EXPECT_EQ(st->raw, 0x0008);  // Op, no error
  EXPECT_EQ(st->code, 0x0000);
}

TEST(InProcessStack, DriveEnablesAndFollowsCspSetPoints) {
  InProcess p;
  p.add_default();
  ASSERT_EQ(p.bring_up(), "");
  // Shutdown, switch on, enable operation (CiA402 transitions 2, 3, 4).
  const std::uint16_t sequence[] = {0x0006, 0x0007, 0x000F};
  const std::uint16_t expect[] = {0x0231, 0x0233, 0x0237};
  for (std::size_t k = 0; k < 3; ++k) {
    for (int c = 0; c < 5; ++c) {
      command(p, sequence[k], 0);
      auto r = p.cycle_once(kCycle);
      ASSERT_TRUE(r);
      ASSERT_EQ(r->wkc, kWkcOneDrive);
    }
    EXPECT_EQ(statusword(p) & 0x027F, expect[k]) << "step " << k;
  }
  // A 1000-cycle ramp of 200000 increments, then 300 cycles holding.
  const std::int32_t distance = 200000;
  for (int c = 0; c <= 1300; ++c) {
    const std::int32_t target = c >= 1000 ? distance : distance / 1000 * c;
    command(p, 0x000F, target);
    auto r = p.cycle_once(kCycle);
    ASSERT_TRUE(r);
    ASSERT_EQ(r->wkc, kWkcOneDrive) << "cycle " << c;
  }
  EXPECT_EQ(statusword(p) & 0x006F, 0x0027) << std::hex << statusword(p);  // still enabled, no fault
  EXPECT_LE(std::abs(actual(p) - distance), 100);  // inside the position window 6067h
}

TEST(InProcessStack, MasterVanishingTripsTheProcessDataWatchdog) {
  InProcess p;
  p.add_default();
  ASSERT_EQ(p.bring_up(), "");
  // No process data for longer than the watchdog (0x0420 x 0x0400 = 100 ms).
  p.advance(std::chrono::milliseconds(150));
  p.advance(std::chrono::milliseconds(1));
  auto st = p.master.read_al_status(0);
  ASSERT_TRUE(st);
  EXPECT_EQ(st->raw, 0x0014);   // SafeOp + ErrInd
  EXPECT_EQ(st->code, 0x001B);  // sync manager watchdog
}

}  // namespace
}  // namespace ecat::test
