// Homing mode (CiA 402-2 §11): methods 1-14 (limit or home switch, then the
// encoder index pulse), 17-30 (the same, ending on the switch edge), 33/34
// (index pulse only), 35 and 37 (current position). Speeds from 6099h,
// acceleration 609Ah; once found, the home position reads as the home offset
// 607Ch. Statusword bits 10/12/13 per Table 58. Manufacturer methods (the
// negative numbers): -3/-4 of the Welcon drive, "current threshold" homing
// on a mechanical stop (docs/ds402.md "Homing").
#pragma once

#include <cstdint>
#include <optional>

#include "ds402/axis.hpp"
#include "ds402/profile.hpp"

namespace ecat::ds402 {

enum class HomingStatus : std::uint8_t {
  NotStarted,   // also "interrupted": bit 10 = 1
  InProgress,   // 0 0 0
  Attained,     // bit 12 = 1 and bit 10 = 1
  Error,        // bit 13 = 1, bit 10 = velocity is 0
};

// What one method does (derived from its number).
struct HomingMethod {
  enum class Kind : std::uint8_t { Edge, Window, IndexOnly, CurrentPosition, CurrentThreshold };
  Kind kind = Kind::CurrentPosition;
  AxisSignal signal = AxisSignal::HomeSwitch;
  int final_direction = 1;      // direction of the last, slow approach
  bool active_before = false;   // signal state before the edge on that approach
  int initial_direction = 1;    // window methods: first search direction
  bool index = false;           // home is the next index pulse after the edge
};

// The method's definition, or nullopt for a number this simulator does not
// define (0, 15, 16, 31, 32, 36, > 37 and the negative ones but -3/-4).
// The negative (manufacturer) numbers are defined here as the Welcon manual
// (seed 000 §5.4.3.33/34) defines them; a personality offers them or not.
std::optional<HomingMethod> homing_method(std::int8_t number) noexcept;

class Homing {
 public:
  struct Speeds {
    double switch_search = 0;  // increments/s (6099h:01)
    double zero_search = 0;    // increments/s (6099h:02)
    double acceleration = 0;   // increments/s² (609Ah)
  };
  // The motor current and the threshold of the current-threshold methods
  // (-3/-4; Welcon 2402h), in mA.
  struct Current {
    double actual_ma = 0;
    double threshold_ma = 0;
  };

  // Starts `method`; false (and status Error) if it is not defined.
  bool start(std::int8_t method, const Axis& axis, double actual_position) noexcept;
  // Drops an active search (start bit cleared or halt): the axis stops at
  // the homing acceleration and the status reads "interrupted".
  void interrupt() noexcept;

  // One cycle. `previous`/`actual`: the physical position at the start and
  // end of the cycle. On completion returns the shift (logical - physical
  // increments) that makes the home position read `home_offset`.
  std::optional<double> cycle(ProfileGenerator& gen, const Axis& axis, double previous, double actual,
                              const Speeds& speeds, double home_offset, double dt,
                              const Current& current) noexcept;

  HomingStatus status() const noexcept { return status_; }
  bool active() const noexcept { return status_ == HomingStatus::InProgress; }
  bool stopping() const noexcept { return stopping_; }

 private:
  enum class Phase : std::uint8_t { SearchWindow, Exit, Final, Index, SearchStop, Stop, Return, Done };
  void fail() noexcept;
  bool limit_ahead(const Axis& axis, double pos, int direction) const noexcept;

  HomingMethod m_;
  HomingStatus status_ = HomingStatus::NotStarted;
  Phase phase_ = Phase::Done;
  int search_direction_ = 1;
  bool reversed_ = false;
  bool stopping_ = false;  // an error or interruption is ramping down
  double event_position_ = 0;
};

}  // namespace ecat::ds402
