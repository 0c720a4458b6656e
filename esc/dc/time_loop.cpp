// DC time control loop; model and register meaning in time_loop.hpp.
#include "esc/dc/time_loop.hpp"

#include <algorithm>
#include <cmath>

namespace ecat::esc {
namespace {

constexpr std::uint16_t kSpeedCounterStartMask = 0x7FFF;  // bits 14:0
constexpr std::uint16_t kSpeedCounterStartMin = 0x0080;
constexpr std::uint16_t kSpeedCounterStartMax = 0x3FFF;
constexpr double kSpeedCounterStartReference = 0x1000;
constexpr std::uint8_t kFilterDepthMask = 0x0F;  // bits 3:0
constexpr double kNsPerSecond = 1e9;
constexpr std::uint32_t kDifferenceMagnitudeMax = 0x7FFFFFFF;
constexpr std::uint32_t kDifferenceNegative = 0x80000000;

}  // namespace

void TimeLoop::restart(std::uint16_t speed_counter_start) noexcept {
  speed_counter_start_ = speed_counter_start;
  omega_ = omega_of(speed_counter_start);
  primed_ = false;
  filtered_ = 0.0;
  frequency_ = 0.0;
}

void TimeLoop::set_filter_depth(std::uint8_t depth) noexcept {
  depth_ = depth;
  filter_gain_ = 1.0 / static_cast<double>(1u << (depth & kFilterDepthMask));
}

double TimeLoop::omega_of(std::uint16_t speed_counter_start) noexcept {
  const auto start = std::clamp<std::uint16_t>(
      static_cast<std::uint16_t>(speed_counter_start & kSpeedCounterStartMask), kSpeedCounterStartMin,
      kSpeedCounterStartMax);
  return std::min(kOmegaReset * kSpeedCounterStartReference / start, kOmegaMax);
}

void TimeLoop::compare(std::int64_t difference, Nanoseconds t, std::uint64_t local,
                       LocalClock& clock) noexcept {
  const auto e = static_cast<double>(difference);
  double dt = 0.0;
  if (!primed_) {
    filtered_ = e;
    primed_ = true;
  } else {
    const auto elapsed = static_cast<std::int64_t>(local - last_local_);
    dt = static_cast<double>(std::clamp<std::int64_t>(elapsed, 0, kMaxInterval.count())) / kNsPerSecond;
    filtered_ += (e - filtered_) * filter_gain_;  // / 2^depth: a power of two, so the same value
  }
  last_local_ = local;
  const double w = omega_;
  const double error_s = filtered_ / kNsPerSecond;  // seconds of phase error
  frequency_ = std::clamp(frequency_ - w * w * error_s * dt, -kMaxRateCorrection, kMaxRateCorrection);
  const double correction = std::clamp(frequency_ - 2.0 * w * error_s, -kMaxRateCorrection, kMaxRateCorrection);
  clock.set_rate_correction(t, correction);
}

std::uint32_t TimeLoop::difference_register() const noexcept {
  const double magnitude = std::min(std::fabs(std::round(filtered_)), static_cast<double>(kDifferenceMagnitudeMax));
  auto v = static_cast<std::uint32_t>(magnitude);
  if (filtered_ < 0.0 && v != 0) v |= kDifferenceNegative;
  return v;
}

std::uint16_t TimeLoop::speed_counter_diff_register() const noexcept {
  constexpr double kMin = -32768.0;
  constexpr double kMax = 32767.0;
  const double counts = std::clamp(std::round(frequency_ / kSpeedCounterDiffUnit), kMin, kMax);
  return static_cast<std::uint16_t>(static_cast<std::int16_t>(counts));
}

}  // namespace ecat::esc
