// One LATCH input of a DC unit (ESC datasheet Section I §9.2.5 "Latch
// signals", Section II 0x09A8-0x09CF): an edge on the pin stores the system
// time of that edge. Single-event mode keeps the first edge until the time
// register is read; continuous mode overwrites on every edge.
#pragma once

#include <cstdint>

namespace ecat::esc {

class LatchUnit {
 public:
  void reset() noexcept { *this = LatchUnit{}; }
  void set_control(std::uint8_t control) noexcept { control_ = control; }
  std::uint8_t control() const noexcept { return control_; }

  // The pin goes to `level` at system time `time`; returns true if an edge
  // was stored (an event for the owner).
  bool input(bool level, std::uint64_t time) noexcept;

  // 0x09AE/0x09AF: bit 0 positive event, bit 1 negative event, bit 2 pin.
  std::uint8_t status() const noexcept;
  std::uint64_t positive_time() const noexcept { return positive_time_; }
  std::uint64_t negative_time() const noexcept { return negative_time_; }
  // Reading a time register (by the owner) clears its event flag.
  void positive_read() noexcept { positive_event_ = false; }
  void negative_read() noexcept { negative_event_ = false; }
  bool event_pending() const noexcept { return positive_event_ || negative_event_; }

 private:
  std::uint8_t control_ = 0;
  bool pin_ = false;
  bool positive_event_ = false;
  bool negative_event_ = false;
  std::uint64_t positive_time_ = 0;
  std::uint64_t negative_time_ = 0;
};

}  // namespace ecat::esc
