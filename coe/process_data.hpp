// Cyclic copy between the process-data sync managers and the objects
// (ETG.1000.6 §5.6.7.4): read_outputs takes SM2's buffer (reading it whole
// hands the 3-buffer back to the ESC) and writes each mapped RxPDO entry;
// write_inputs packs the mapped TxPDO entries and writes SM3's buffer (its
// last byte completes it). Layout from PdoConfig; the frame buffer is sized
// once; no heap on this path.
#pragma once

#include <cstdint>
#include <vector>

#include "coe/object_store.hpp"
#include "coe/pdo_config.hpp"
#include "esc/pdi.hpp"

namespace ecat::coe {

class ProcessData {
 public:
  ProcessData(ObjectStore& store, PdoConfig& config);

  // SM2 -> objects. Call in Op (outputs are not valid before).
  void read_outputs(esc::Pdi& pdi) noexcept;
  // Objects -> SM3. Call in SafeOp and Op.
  void write_inputs(esc::Pdi& pdi) noexcept;

  const ProcessDataImage& outputs() const noexcept { return config_.outputs(); }
  const ProcessDataImage& inputs() const noexcept { return config_.inputs(); }

 private:
  ObjectStore& store_;
  PdoConfig& config_;
  std::vector<std::uint8_t> buffer_;
};

}  // namespace ecat::coe
