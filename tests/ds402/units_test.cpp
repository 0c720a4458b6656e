// The output rounding (UnitScaling::to_i32/to_i16, inline) against the
// definition it replaces: std::round, then saturation, NaN as 0.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "ds402/units.hpp"

namespace ecat::ds402::test {
namespace {

std::int32_t reference_i32(double v) {
  if (std::isnan(v)) return 0;
  const double r = std::round(v);
  if (r >= 2147483647.0) return INT32_MAX;
  if (r <= -2147483648.0) return INT32_MIN;
  return static_cast<std::int32_t>(r);
}

std::int16_t reference_i16(double v) {
  if (std::isnan(v)) return 0;
  const double r = std::round(v);
  if (r >= 32767.0) return INT16_MAX;
  if (r <= -32768.0) return INT16_MIN;
  return static_cast<std::int16_t>(r);
}

std::vector<double> edge_values() {
  std::vector<double> v = {0.0, -0.0, 0.5, -0.5, 1.5, -1.5, 2.5, -2.5, 0.49999999999999994, -0.49999999999999994,
                           std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::denorm_min(),
                           1e300, -1e300, 4503599627370495.5, 4503599627370497.0};
  for (const double base : {2147483647.0, -2147483648.0, 32767.0, -32768.0, 65535.0, 4294967296.0}) {
    for (double d = -2.0; d <= 2.0; d += 0.25) {
      v.push_back(base + d);
      v.push_back(std::nextafter(base + d, HUGE_VAL));
      v.push_back(std::nextafter(base + d, -HUGE_VAL));
    }
  }
  return v;
}

TEST(OutputRounding, MatchesStdRoundAtTheEdges) {
  for (const double v : edge_values()) {
    EXPECT_EQ(UnitScaling::to_i32(v), reference_i32(v)) << v;
    EXPECT_EQ(UnitScaling::to_i16(v), reference_i16(v)) << v;
  }
}

TEST(OutputRounding, MatchesStdRoundOnPseudoRandomValues) {
  std::uint64_t s = 0x9E3779B97F4A7C15ull;
  for (int i = 0; i < 200000; ++i) {
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    const double unit = static_cast<double>(s >> 11) / 9007199254740992.0;  // [0, 1)
    const double scale = std::ldexp(1.0, static_cast<int>((s >> 3) % 40) - 4);  // 1/16 .. 2^35
    const double v = (unit - 0.5) * 2 * scale;
    ASSERT_EQ(UnitScaling::to_i32(v), reference_i32(v)) << v;
    ASSERT_EQ(UnitScaling::to_i16(v), reference_i16(v)) << v;
    const double half = std::floor(v) + 0.5;  // exact halves
    ASSERT_EQ(UnitScaling::to_i32(half), reference_i32(half)) << half;
    ASSERT_EQ(UnitScaling::to_i16(half), reference_i16(half)) << half;
  }
}

}  // namespace
}  // namespace ecat::ds402::test
