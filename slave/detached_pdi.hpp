// A PDI to nothing: reads give zeros, writes are dropped. The built-in
// firmware of a slave whose real firmware is another process
// (SlaveOptions::external_firmware) is built over it, so the slave keeps its
// dictionary for the control interface while that firmware never touches
// the ESC.
#pragma once

#include <algorithm>

#include "esc/pdi.hpp"

namespace ecat::slave {

class DetachedPdi final : public esc::Pdi {
 public:
  void read(std::uint16_t /*address*/, std::span<std::uint8_t> out) noexcept override {
    std::fill(out.begin(), out.end(), std::uint8_t{0});
  }
  void write(std::uint16_t /*address*/, std::span<const std::uint8_t> /*in*/) noexcept override {}
};

}  // namespace ecat::slave
