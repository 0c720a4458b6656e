#include "coe/process_data.hpp"

#include <algorithm>
#include <cstring>

#include "coe/bit_copy.hpp"
#include "coe/sm_bits.hpp"
#include "esc/registers.hpp"

namespace ecat::coe {
namespace {

constexpr unsigned kBitsPerByte = 8;

void copy_out(std::uint8_t* value, const std::uint8_t* image, const PdoItem& item) noexcept {
  if (item.bit_offset == 0 && item.bits % kBitsPerByte == 0) {
    std::memcpy(value, image + item.byte_offset, item.bits / kBitsPerByte);
  } else {
    get_bits(value, image, item.bit_position(), item.bits);
  }
}

void copy_in(std::uint8_t* image, const std::uint8_t* value, const PdoItem& item) noexcept {
  if (item.bit_offset == 0 && item.bits % kBitsPerByte == 0) {
    std::memcpy(image + item.byte_offset, value, item.bits / kBitsPerByte);
  } else {
    put_bits(image, item.bit_position(), value, item.bits);
  }
}

}  // namespace

ProcessData::ProcessData(ObjectStore& store, PdoConfig& config)
    : store_(store),
      config_(config),
      buffer_(std::max(config.max_bytes(PdoDirection::Rx), config.max_bytes(PdoDirection::Tx))) {}

ProcessData::SmArea ProcessData::area(esc::Pdi& pdi, unsigned sm) noexcept {
  if (layout_loaded_) return areas_[sm == kOutputsSm ? 0 : 1];
  std::uint8_t raw[esc::reg::kSyncManagerStride]{};
  pdi.read(esc::reg::sync_manager(sm), raw);
  return {load_le<std::uint16_t>(raw + esc::reg::sm::kStartAddress), load_le<std::uint16_t>(raw + esc::reg::sm::kLength),
          (raw[esc::reg::sm::kActivate] & bits::kSmActivateEnable) != 0};
}

void ProcessData::load_layout(esc::Pdi& pdi) noexcept {
  layout_loaded_ = false;
  areas_ = {area(pdi, kOutputsSm), area(pdi, kInputsSm)};
  layout_loaded_ = true;
}

void ProcessData::read_outputs(esc::Pdi& pdi) noexcept {
  const ProcessDataImage& image = config_.outputs();
  const SmArea sm = area(pdi, kOutputsSm);
  if (!sm.enabled || sm.length == 0 || sm.length > buffer_.size() || sm.length < image.byte_length()) return;
  pdi.read(sm.start, {buffer_.data(), sm.length});
  for (const PdoItem& item : image.items()) {
    if (item.entry) copy_out(store_.storage(*item.entry).data(), buffer_.data(), item);
  }
}

void ProcessData::write_inputs(esc::Pdi& pdi) noexcept {
  const ProcessDataImage& image = config_.inputs();
  const SmArea sm = area(pdi, kInputsSm);
  if (!sm.enabled || sm.length == 0 || sm.length > buffer_.size() || sm.length < image.byte_length()) return;
  std::fill(buffer_.begin(), buffer_.begin() + sm.length, std::uint8_t{0});
  for (const PdoItem& item : image.items()) {
    if (item.entry) copy_in(buffer_.data(), store_.value(*item.entry).data(), item);
  }
  pdi.write(sm.start, {buffer_.data(), sm.length});
}

}  // namespace ecat::coe
