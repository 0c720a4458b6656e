// Where each mapped object sits in a slave's process data, read from the
// slave itself over SDO (1C12h/1C13h assignment, 16xxh/1Axxh mapping), the
// way a master finds its variables when it has no ESI.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/expected.hpp"
#include "master/coe_client.hpp"

namespace ecat::app {

struct MappedObject {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  std::uint8_t bits = 0;
  std::uint32_t bit_offset = 0;  // from the start of the slave's outputs or inputs
};

struct PdoLocator {
  std::vector<MappedObject> outputs;  // RxPDOs, SM2
  std::vector<MappedObject> inputs;   // TxPDOs, SM3

  static Expected<PdoLocator, std::string> read(master::CoeClient& coe);
  std::optional<std::uint32_t> output_byte(std::uint16_t index, std::uint8_t subindex = 0) const;
  std::optional<std::uint32_t> input_byte(std::uint16_t index, std::uint8_t subindex = 0) const;
};

}  // namespace ecat::app
