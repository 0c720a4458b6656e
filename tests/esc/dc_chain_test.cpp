// Issue 6 acceptance: three slaves with ±100 ppm clocks, a master's standard
// DC set-up (delay measurement, offsets, static drift compensation by repeated
// ARMW, then one ARMW per 1 ms cycle) converge to |0x092C| < 100 ns and hold.
// The measured numbers are printed for docs/dc.md.
#include <gtest/gtest.h>

#include <iostream>

#include "dc_chain.hpp"

namespace ecat::esc::test {
namespace {

constexpr std::uint64_t kSystemStart = 0x0A00'0000'0000'0000ull;  // some time in 2022 since 2000
constexpr Nanoseconds kHop{600};
constexpr std::int64_t kLimitNs = 100;

DcChain<3> make_chain() {
  return DcChain<3>({+100.0, -100.0, +60.0}, {1'000'000'000ull, 5'000'000'000'000ull, 123'456ull}, kHop);
}

TEST(DcChain, DelayMeasurementGivesHopMultiples) {
  auto chain = make_chain();
  chain.configure(ms(1), kSystemStart);
  // Port times are local times, so the ±100 ppm clocks skew them by < 1 ns.
  EXPECT_EQ(chain.delay(0), 0u);
  EXPECT_NEAR(static_cast<double>(chain.delay(1)), 600.0, 1.0);
  EXPECT_NEAR(static_cast<double>(chain.delay(2)), 1200.0, 1.0);
  // The offsets make all system times agree ...
  EXPECT_LT(chain.worst_true_error(ms(1)), 5);  // at the latch instant; they drift apart after
}

TEST(DcChain, StaticDriftCompensationThenCyclicHolds) {
  auto chain = make_chain();
  chain.configure(ms(1), kSystemStart);
  constexpr int kBurst = 15000;  // "the spec recommends ~15 000" (ethercrab notes)
  constexpr Nanoseconds kBurstPeriod = us(100);
  Nanoseconds t = ms(3);
  int converged_at = -1;  // first ARMW after which |0x092C| stays < 100 ns
  std::int64_t peak = 0;
  for (int n = 0; n < kBurst; ++n, t += kBurstPeriod) {
    chain.armw_system_time(t);
    const std::int64_t d = chain.worst_difference(t);
    peak = std::max(peak, d);
    if (d >= kLimitNs) {
      converged_at = -1;
    } else if (converged_at < 0) {
      converged_at = n;
    }
  }
  ASSERT_GE(converged_at, 0);
  constexpr int kCycles = 5000;  // 5 s of 1 ms cycles
  std::int64_t steady = 0;
  std::int64_t steady_true = 0;
  for (int c = 0; c < kCycles; ++c, t += ms(1)) {
    chain.armw_system_time(t);
    steady = std::max(steady, chain.worst_difference(t));
    steady_true = std::max(steady_true, chain.worst_true_error(t + us(500)));
  }
  EXPECT_LT(steady, kLimitNs);
  EXPECT_LT(steady_true, kLimitNs);
  std::cout << "[dc] burst: converged after " << converged_at + 1 << " ARMW (100 us apart), peak |0x092C| "
            << peak << " ns; 1 ms cycles: max |0x092C| " << steady << " ns, max true error " << steady_true
            << " ns\n";
}

TEST(DcChain, CyclicOnlyConvergesToo) {
  // IgH: no static burst, one FRMW/ARMW per application cycle from the start.
  auto chain = make_chain();
  chain.configure(ms(1), kSystemStart);
  Nanoseconds t = ms(3);
  int converged_at = -1;
  std::int64_t peak = 0;
  constexpr int kCycles = 6000;
  std::int64_t late = 0;
  for (int c = 0; c < kCycles; ++c, t += ms(1)) {
    chain.armw_system_time(t);
    const std::int64_t d = chain.worst_difference(t);
    peak = std::max(peak, d);
    if (d >= kLimitNs) {
      converged_at = -1;
    } else if (converged_at < 0) {
      converged_at = c;
    }
    if (c >= kCycles - 1000) late = std::max(late, chain.worst_true_error(t + us(500)));
  }
  ASSERT_GE(converged_at, 0);
  EXPECT_LT(converged_at, 2000);
  EXPECT_LT(late, kLimitNs);
  std::cout << "[dc] cyclic only: converged after " << converged_at + 1 << " cycles of 1 ms, peak |0x092C| " << peak
            << " ns, max true error over the last second " << late << " ns\n";
}

}  // namespace
}  // namespace ecat::esc::test
