// LATCH input; behaviour in latch_unit.hpp.
#include "esc/dc/latch_unit.hpp"

#include "esc/dc/dc_registers.hpp"

namespace ecat::esc {

bool LatchUnit::input(bool level, std::uint64_t time) noexcept {
  if (level == pin_) return false;
  pin_ = level;
  if (level) {
    const bool single = (control_ & dcreg::kLatchPositiveSingle) != 0;
    if (single && positive_event_) return false;
    positive_time_ = time;
    positive_event_ = true;
  } else {
    const bool single = (control_ & dcreg::kLatchNegativeSingle) != 0;
    if (single && negative_event_) return false;
    negative_time_ = time;
    negative_event_ = true;
  }
  return true;
}

std::uint8_t LatchUnit::status() const noexcept {
  std::uint8_t s = 0;
  if (positive_event_) s |= dcreg::kLatchPositiveEvent;
  if (negative_event_) s |= dcreg::kLatchNegativeEvent;
  if (pin_) s |= dcreg::kLatchPinState;
  return s;
}

}  // namespace ecat::esc
