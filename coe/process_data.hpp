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
#include <span>
#include <vector>

#include "coe/object_store.hpp"
#include "coe/pdo_config.hpp"
#include "common/cache_line.hpp"
#include "esc/pdi.hpp"

namespace ecat::coe {

class ProcessData {
 public:
  // Counts `config`'s rebuilds (PdoConfig::count_rebuilds_in): `config`
  // must not rebuild after this ProcessData is gone, and it stays put.
  ProcessData(ObjectStore& store, PdoConfig& config);
  ProcessData(const ProcessData&) = delete;
  ProcessData& operator=(const ProcessData&) = delete;

  // SM2 -> objects. Call in Op (outputs are not valid before).
  void read_outputs(esc::Pdi& pdi) noexcept;
  // Objects -> SM3. Call in SafeOp and Op.
  void write_inputs(esc::Pdi& pdi) noexcept;

  // Reads the process-data SMs (start, length, enable) once for the following cycles.
  void load_layout(esc::Pdi& pdi) noexcept;

  const ProcessDataImage& outputs() const noexcept { return *outputs_; }
  const ProcessDataImage& inputs() const noexcept { return *inputs_; }
  // outputs().items() as of the last rebuild of the mapping, from this
  // object's own members (what an application's cycle reads: the image's
  // line stays out of it).
  std::span<const PdoItem> output_items() noexcept {
    refresh_plans();
    return output_items_;
  }

 private:
  struct SmArea {
    std::uint16_t start = 0;
    std::uint16_t length = 0;
    bool enabled = false;
  };
  // The copies of one image decoded once (issue 8): per mapped entry its
  // value bytes and its place in the SM buffer; whole bytes are copied as
  // such, other items bit by bit from their PdoItem. Rebuilt when the
  // image's generation changes; sized for the image's capacity, so a rebuild
  // does not allocate either.
  // 16 bytes, four to a cache line: the plans are read every cycle, and at
  // 1000 slaves every line of them is a last-level miss (docs/performance-log.md
  // "Session 14").
  struct Copy {
    std::uint8_t* value = nullptr;
    std::uint32_t at = 0;    // bytes != 0: the byte offset in the SM; else the item's index in the image
    std::uint16_t bytes = 0;  // 0: bit copy of image.items()[at]
  };
  static_assert(sizeof(Copy) <= 16);
  // One checked process-data SM: everything a cycle reads of it but its
  // image and its copies, in one cache line and aligned to it (issue 30
  // item 1: at 1000 drives the SM list, the areas and the plans were a line
  // each; unaligned, two SMs' took three lines).
  struct alignas(kCacheLineBytes) SmCopy {
    const ProcessDataImage* image = nullptr;  // in the PdoConfig, fixed after its construction
    std::vector<Copy> copies;
    std::uint64_t generation = ~std::uint64_t{0};  // of the image the copies were made from
    // Whole-byte copies that write every byte of [0, covered) and nothing
    // else: write_inputs zeroes the buffer first only when the SM is longer
    // (or the image has gaps or bit items). 0 when not so.
    std::uint32_t covered = 0;
    std::uint32_t byte_length = 0;  // the image's, with the copies
    SmArea area;         // from load_layout()
    std::uint8_t sm = 0;  // its number
  };
  static_assert(sizeof(SmCopy) == kCacheLineBytes, "one cache line");
  // The copies for each image's current layout, rebuilt where it changed,
  // when the PdoConfig rebuilt the images since the last look.
  void refresh_plans() noexcept {
    if (rebuilds_seen_ != rebuilds_) refresh();
  }
  [[gnu::noinline]] void refresh() noexcept;
  void rebuild(SmCopy& c) noexcept;
  SmArea area(esc::Pdi& pdi, const SmCopy& c) noexcept;

  void read_sm(esc::Pdi& pdi, SmCopy& c) noexcept;
  void write_sm(esc::Pdi& pdi, SmCopy& c) noexcept;

  ObjectStore& store_;
  // The PdoConfig's rebuilds, counted by it, and the count the plans and
  // output_items_ were last brought up to date at.
  std::uint64_t rebuilds_ = 0;
  std::uint64_t rebuilds_seen_ = ~std::uint64_t{0};
  std::span<const PdoItem> output_items_;
  // The checked process-data SMs of the PdoConfig's sms() in their order, the
  // outputs (Rx) ones first: [0, rx_count_) read, the rest written.
  std::vector<SmCopy> sms_;
  std::size_t rx_count_ = 0;
  bool layout_loaded_ = false;
  const ProcessDataImage* outputs_;
  const ProcessDataImage* inputs_;
  std::vector<std::uint8_t> buffer_;
};

}  // namespace ecat::coe
