// A line of DC units and a master-like DC set-up over it, in simulated time:
// a frame sent at t0 reaches slave k's port 0 at t0 + k * hop and comes back
// through port 1 of slave k at t0 + (2(n-1) - k) * hop (the last slave's
// port 1 is closed and loops the frame back at once).
#pragma once

#include <array>
#include <cstdint>
#include <cstdlib>

#include "dc_fixture.hpp"

namespace ecat::esc::test {

template <std::size_t N>
class DcChain {
 public:
  DcChain(const std::array<double, N>& ppm, const std::array<std::uint64_t, N>& start, Nanoseconds hop)
      : hop_(hop) {
    for (std::size_t k = 0; k < N; ++k) {
      units_[k].set_clock(ppm[k], start[k]);
      units_[k].reset(0);
    }
  }

  DcUnit& operator[](std::size_t k) { return units_[k]; }
  Nanoseconds arrival(Nanoseconds t0, std::size_t k) const { return t0 + hop_ * static_cast<std::int64_t>(k); }

  // One frame through the chain; visit(k, t) is the datagram's action at slave k.
  template <typename Visit>
  void frame(Nanoseconds t0, Visit&& visit) {
    for (std::size_t k = 0; k < N; ++k) {
      units_[k].on_frame_arrival(0, arrival(t0, k));
      visit(k, arrival(t0, k));
    }
    for (std::size_t k = N - 1; k-- > 0;) {
      units_[k].on_frame_arrival(1, arrival(t0, N - 1) + hop_ * static_cast<std::int64_t>(N - 1 - k));
    }
  }

  // BWR 0x0900, then the delay and offset computation every master does
  // (shared/spec/masters.md: ethercrab dc.rs, IgH fsm_slave_config), written
  // with FPWR 0x0920 / 0x0928 and a 0x0930 restart. Slave 0 is the reference;
  // its system time starts at `system_start`.
  void configure(Nanoseconds t0, std::uint64_t system_start) {
    frame(t0, [&](std::size_t k, Nanoseconds t) { dc_write(units_[k], dcreg::kReceiveTimePort0, 0, 4, t); });
    const Nanoseconds later = t0 + ms(1);
    std::array<std::uint32_t, N> loop{};
    std::array<std::uint64_t, N> rx{};
    for (std::size_t k = 0; k < N; ++k) {
      const auto p0 = static_cast<std::uint32_t>(dc_read(units_[k], dcreg::kReceiveTimePort0, 4, later));
      const auto p1 = static_cast<std::uint32_t>(dc_read(units_[k], dcreg::kReceiveTimePort0 + 4, 4, later));
      loop[k] = k + 1 < N ? p1 - p0 : 0;  // last slave: port 1 closed
      rx[k] = dc_read(units_[k], dcreg::kReceiveTimeProcessingUnit, 8, later);
    }
    std::uint64_t delay = 0;
    const std::uint64_t ref_offset = system_start - rx[0];
    for (std::size_t k = 0; k < N; ++k) {
      if (k > 0) delay += (loop[k - 1] - loop[k]) / 2;
      delays_[k] = delay;
      const std::uint64_t offset = rx[0] + ref_offset + delay - rx[k];
      dc_write(units_[k], dcreg::kSystemTimeOffset, offset, 8, later);
      dc_write(units_[k], dcreg::kSystemTimeDelay, delay, 4, later);
      dc_write(units_[k], dcreg::kSpeedCounterStart, dcreg::kSpeedCounterStartReset, 2, later);
    }
  }

  // ARMW 0x0910 addressed at slave 0: read there, write everywhere after it.
  void armw_system_time(Nanoseconds t0) {
    std::uint64_t value = 0;
    frame(t0, [&](std::size_t k, Nanoseconds t) {
      if (k == 0) {
        value = dc_read(units_[k], dcreg::kSystemTime, 8, t);
      } else {
        dc_write(units_[k], dcreg::kSystemTime, value, 8, t);
      }
    });
  }

  // 0x092C of slave k as a signed number (bit 31 = local copy behind).
  std::int64_t difference(std::size_t k, Nanoseconds t) {
    const auto raw = static_cast<std::uint32_t>(dc_read(units_[k], dcreg::kSystemTimeDifference, 4, t));
    const std::int64_t magnitude = raw & 0x7FFF'FFFFu;
    return (raw & 0x8000'0000u) != 0 ? -magnitude : magnitude;
  }
  // Largest |0x092C| over the non-reference slaves.
  std::int64_t worst_difference(Nanoseconds t) {
    std::int64_t worst = 0;
    for (std::size_t k = 1; k < N; ++k) worst = std::max(worst, std::abs(difference(k, t)));
    return worst;
  }
  // Largest true disagreement of system times at one true instant.
  std::int64_t worst_true_error(Nanoseconds t) {
    std::int64_t worst = 0;
    const std::uint64_t ref = units_[0].system_time(t);
    for (std::size_t k = 1; k < N; ++k) {
      worst = std::max(worst, std::abs(static_cast<std::int64_t>(units_[k].system_time(t) - ref)));
    }
    return worst;
  }
  std::uint64_t delay(std::size_t k) const { return delays_[k]; }

 private:
  std::array<DcUnit, N> units_{};
  std::array<std::uint64_t, N> delays_{};
  Nanoseconds hop_;
};

}  // namespace ecat::esc::test
