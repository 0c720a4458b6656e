// A drive under test: fixed 1 ms cycles of simulated time.
#pragma once

#include <chrono>
#include <cstdint>

#include "ds402/drive.hpp"

namespace ecat::ds402::test {

inline constexpr std::chrono::milliseconds kCycle{1};

struct Harness {
  explicit Harness(DriveConfig config = generic_drive(), PlantParameters plant = {})
      : drive(std::move(config), plant) {
    step();
  }
  void step() { drive.step(in, out, kCycle); }
  void run(int cycles) {
    for (int i = 0; i < cycles; ++i) step();
  }
  // Steps until `done` is true or `limit` cycles passed; returns the cycles taken (or -1).
  template <typename F>
  int run_until(F done, int limit) {
    for (int i = 1; i <= limit; ++i) {
      step();
      if (done()) return i;
    }
    return -1;
  }
  void command(std::uint16_t controlword) {
    in.controlword = controlword;
    step();
  }
  // Shutdown, switch on, enable operation in `mode`.
  void enable(OperationMode mode) {
    in.modes_of_operation = static_cast<std::int8_t>(mode);
    command(0x0006);
    command(0x0007);
    command(0x000F);
  }
  std::uint16_t status() const { return out.statusword; }
  bool bit(std::uint16_t mask) const { return (out.statusword & mask) != 0; }

  DriveInputs in;
  DriveOutputs out;
  Drive drive;
};

}  // namespace ecat::ds402::test
