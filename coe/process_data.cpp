#include "coe/process_data.hpp"

#include <algorithm>

#include "coe/bit_copy.hpp"
#include "coe/sm_bits.hpp"
#include "esc/registers.hpp"

namespace ecat::coe {
namespace {

struct SmArea {
  std::uint16_t start = 0;
  std::uint16_t length = 0;
  bool enabled = false;
};

SmArea read_area(esc::Pdi& pdi, unsigned sm) noexcept {
  std::uint8_t raw[esc::reg::kSyncManagerStride]{};
  pdi.read(esc::reg::sync_manager(sm), raw);
  return {load_le<std::uint16_t>(raw + esc::reg::sm::kStartAddress), load_le<std::uint16_t>(raw + esc::reg::sm::kLength),
          (raw[esc::reg::sm::kActivate] & bits::kSmActivateEnable) != 0};
}

}  // namespace

ProcessData::ProcessData(ObjectStore& store, PdoConfig& config)
    : store_(store),
      config_(config),
      buffer_(std::max(config.max_bytes(PdoDirection::Rx), config.max_bytes(PdoDirection::Tx))) {}

void ProcessData::read_outputs(esc::Pdi& pdi) noexcept {
  const ProcessDataImage& image = config_.outputs();
  const SmArea sm = read_area(pdi, kOutputsSm);
  if (!sm.enabled || sm.length == 0 || sm.length > buffer_.size() || sm.length < image.byte_length()) return;
  pdi.read(sm.start, {buffer_.data(), sm.length});
  for (const PdoItem& item : image.items()) {
    if (!item.entry) continue;
    get_bits(store_.storage(*item.entry).data(), buffer_.data(), item.bit_position(), item.bits);
  }
}

void ProcessData::write_inputs(esc::Pdi& pdi) noexcept {
  const ProcessDataImage& image = config_.inputs();
  const SmArea sm = read_area(pdi, kInputsSm);
  if (!sm.enabled || sm.length == 0 || sm.length > buffer_.size() || sm.length < image.byte_length()) return;
  std::fill(buffer_.begin(), buffer_.begin() + sm.length, std::uint8_t{0});
  for (const PdoItem& item : image.items()) {
    if (!item.entry) continue;
    put_bits(buffer_.data(), item.bit_position(), store_.value(*item.entry).data(), item.bits);
  }
  pdi.write(sm.start, {buffer_.data(), sm.length});
}

}  // namespace ecat::coe
