// Drives one CiA402 slave through its process data the way a motion master
// does (IEC 61800-7-201 / CiA402 §6.3 state machine): fault reset, shutdown,
// switch on, enable operation, then a smooth move in cyclic synchronous
// position mode (6060h = 8), one set-point per cycle.
#pragma once

#include <cstdint>

#include "apps/ecat-master/pdo_locator.hpp"
#include "master/master.hpp"

namespace ecat::app {

class Cia402Motion {
 public:
  Cia402Motion(master::Master& master, std::size_t slave, const PdoLocator& pdos);

  // True when controlword, statusword, target and actual position are mapped.
  bool usable() const noexcept { return usable_; }
  // Sets the outputs for cycle `cycle` of `cycles` from the last inputs.
  void cycle(std::uint64_t cycle, std::uint64_t cycles, std::int32_t distance) noexcept;

  std::uint16_t statusword() const noexcept;
  std::int32_t actual_position() const noexcept;
  bool operation_enabled() const noexcept;

 private:
  master::Master& master_;
  std::size_t slave_;
  bool usable_ = false;
  std::uint32_t controlword_ = 0, mode_ = 0, target_ = 0;
  std::uint32_t statusword_ = 0, actual_ = 0;
  bool has_mode_ = false;
  bool enabled_ = false;
  std::uint64_t enabled_at_ = 0;
  std::int32_t start_position_ = 0;
  std::uint16_t last_controlword_ = 0;
};

}  // namespace ecat::app
