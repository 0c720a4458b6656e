// Cyclic copy between the process-data sync managers and the objects
// (ETG.1000.6 §5.6.7.4): read_outputs takes each outputs SM's buffer (SM2
// on most devices; reading it whole hands the 3-buffer back to the ESC) and
// writes each mapped RxPDO entry; write_inputs packs the mapped TxPDO
// entries and writes each inputs SM's buffer (its last byte completes it).
// A device with several SMs per direction (EK1828: SM0 and SM1 outputs) has
// one copy per SM, each from the PDOs its 1C10h+n assigns. Layout from PdoConfig; the frame buffer is sized
// once; no heap on this path. Both go through the Pdi's whole-buffer calls
// (read_buffer, write_buffer_begin/commit): on the emulated ESC the entries
// are copied straight between its 3-buffer and the objects (issue 8).
//
// Firmware that knows when the SM settings can change (the master writes SM
// registers only with an SM activation event, and the mapping only in PreOp)
// calls load_layout() then, as SSC reads the SM settings at PreOp->SafeOp:
// the cycle then uses the SM areas read there instead of reading the SM
// registers every time. Without load_layout() each call reads them.
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

  // Reads the process-data SMs (start, length, enable) once for the following cycles.
  void load_layout(esc::Pdi& pdi) noexcept;

  const ProcessDataImage& outputs() const noexcept { return config_.outputs(); }
  const ProcessDataImage& inputs() const noexcept { return config_.inputs(); }

 private:
  struct SmArea {
    std::uint16_t start = 0;
    std::uint16_t length = 0;
    bool enabled = false;
  };
  SmArea area(esc::Pdi& pdi, std::size_t k) noexcept;
  // The copies of one image decoded once (issue 8): per mapped entry its
  // value bytes and its place in the SM buffer; whole bytes are copied as
  // such, other items bit by bit from their PdoItem. Rebuilt when the
  // image's generation changes; sized for the image's capacity, so a rebuild
  // does not allocate either.
  // 16 bytes, four to a cache line: the plans are read every cycle, and at
  // 1000 slaves every line of them is a last-level miss (docs/performance.md
  // "Session 14").
  struct Copy {
    std::uint8_t* value = nullptr;
    std::uint32_t at = 0;    // bytes != 0: the byte offset in the SM; else the item's index in the image
    std::uint16_t bytes = 0;  // 0: bit copy of image.items()[at]
  };
  static_assert(sizeof(Copy) <= 16);
  struct Plan {
    std::vector<Copy> copies;
    std::uint64_t generation = ~std::uint64_t{0};
    // Whole-byte copies that write every byte of [0, covered) and nothing
    // else: write_inputs zeroes the buffer first only when the SM is longer
    // (or the image has gaps or bit items). 0 when not so.
    std::uint32_t covered = 0;
  };
  // The plan for the image's current layout (rebuilt in rebuild() when it changed).
  const Plan& plan(const ProcessDataImage& image, Plan& p) noexcept {
    if (p.generation != image.generation()) rebuild(image, p);
    return p;
  }
  void rebuild(const ProcessDataImage& image, Plan& p) noexcept;

  void read_sm(esc::Pdi& pdi, std::size_t k) noexcept;
  void write_sm(esc::Pdi& pdi, std::size_t k) noexcept;

  ObjectStore& store_;
  PdoConfig& config_;
  std::vector<std::uint8_t> buffer_;
  // Per process-data SM of config_.sms(), same order: its area (from
  // load_layout()) and its copy plan.
  std::vector<SmArea> areas_;
  std::vector<Plan> plans_;
  bool layout_loaded_ = false;
};

}  // namespace ecat::coe
