#include "coe/process_data.hpp"

#include <algorithm>
#include <cstring>

#include "coe/bit_copy.hpp"
#include "coe/sm_bits.hpp"
#include "esc/registers.hpp"
#include "esc/small_copy.hpp"

namespace ecat::coe {
namespace {

constexpr unsigned kBitsPerByte = 8;

}  // namespace

ProcessData::ProcessData(ObjectStore& store, PdoConfig& config)
    : store_(store),
      config_(config),
      buffer_(std::max(config.max_bytes(PdoDirection::Rx), config.max_bytes(PdoDirection::Tx))),
      areas_(config.sms().size()),
      plans_(config.sms().size()) {
  for (std::size_t k = 0; k < plans_.size(); ++k) plans_[k].copies.reserve(config.sms()[k].image.capacity());
}

void ProcessData::rebuild(const ProcessDataImage& image, Plan& p) noexcept {
  p.copies.clear();
  // Items lie in image order, packed: whole-byte items from offset 0 on
  // without a gap or a bit item cover their bytes exactly.
  std::uint32_t covered = 0;
  bool contiguous = true;
  const std::span<const PdoItem> items = image.items();
  for (std::size_t i = 0; i < items.size(); ++i) {
    const PdoItem& item = items[i];
    if (!item.entry) {  // a gap
      contiguous = false;
      continue;
    }
    Copy c;
    c.value = store_.storage(*item.entry).data();
    if (item.bit_offset == 0 && item.bits % kBitsPerByte == 0) {
      c.at = item.byte_offset;
      c.bytes = static_cast<std::uint16_t>(item.bits / kBitsPerByte);
      contiguous = contiguous && c.at == covered;
      covered += c.bytes;
    } else {
      c.at = static_cast<std::uint32_t>(i);  // below the image's capacity, a std::uint32_t
      contiguous = false;
    }
    p.copies.push_back(c);  // within the reserved capacity: the image holds at most that many
  }
  p.covered = contiguous ? covered : 0;
  p.generation = image.generation();
}

ProcessData::SmArea ProcessData::area(esc::Pdi& pdi, std::size_t k) noexcept {
  if (layout_loaded_) return areas_[k];
  std::uint8_t raw[esc::reg::kSyncManagerStride]{};
  pdi.read(esc::reg::sync_manager(config_.sms()[k].sm), raw);
  return {load_le<std::uint16_t>(raw + esc::reg::sm::kStartAddress), load_le<std::uint16_t>(raw + esc::reg::sm::kLength),
          (raw[esc::reg::sm::kActivate] & bits::kSmActivateEnable) != 0};
}

void ProcessData::load_layout(esc::Pdi& pdi) noexcept {
  layout_loaded_ = false;
  for (std::size_t k = 0; k < areas_.size(); ++k) areas_[k] = area(pdi, k);
  layout_loaded_ = true;
}

void ProcessData::read_outputs(esc::Pdi& pdi) noexcept {
  const auto sms = config_.sms();
  for (std::size_t k = 0; k < sms.size(); ++k) {
    if (sms[k].direction == PdoDirection::Rx && sms[k].checked) read_sm(pdi, k);
  }
}

void ProcessData::write_inputs(esc::Pdi& pdi) noexcept {
  const auto sms = config_.sms();
  for (std::size_t k = 0; k < sms.size(); ++k) {
    if (sms[k].direction == PdoDirection::Tx && sms[k].checked) write_sm(pdi, k);
  }
}

void ProcessData::read_sm(esc::Pdi& pdi, std::size_t k) noexcept {
  const ProcessDataImage& image = config_.sms()[k].image;
  const SmArea sm = area(pdi, k);
  if (!sm.enabled || sm.length == 0 || sm.length > buffer_.size() || sm.length < image.byte_length()) return;
  // In place where the PDI can (the ESC's 3-buffer), else through buffer_.
  const std::uint8_t* buffer = pdi.read_buffer(sm.start, {buffer_.data(), sm.length}).data();
  for (const Copy& c : plan(image, plans_[k]).copies) {
    if (c.bytes != 0) {
      esc::copy_small(c.value, buffer + c.at, c.bytes);
    } else {
      const PdoItem& item = image.items()[c.at];
      get_bits(c.value, buffer, item.bit_position(), item.bits);
    }
  }
}

void ProcessData::write_sm(esc::Pdi& pdi, std::size_t k) noexcept {
  const ProcessDataImage& image = config_.sms()[k].image;
  const SmArea sm = area(pdi, k);
  if (!sm.enabled || sm.length == 0 || sm.length > buffer_.size() || sm.length < image.byte_length()) return;
  const Plan& p = plan(image, plans_[k]);
  const std::span<std::uint8_t> place = pdi.write_buffer_begin(sm.start, {buffer_.data(), sm.length});
  std::uint8_t* buffer = place.data();
  // Bytes no copy writes are 0 (gaps, padding, the rest of a longer SM).
  if (p.covered != sm.length) std::memset(buffer, 0, place.size());
  for (const Copy& c : p.copies) {
    if (c.bytes != 0) {
      esc::copy_small(buffer + c.at, c.value, c.bytes);
    } else {
      const PdoItem& item = image.items()[c.at];
      put_bits(buffer, item.bit_position(), c.value, item.bits);
    }
  }
  pdi.write_buffer_commit(sm.start, place);
}

}  // namespace ecat::coe
