#include "coe/process_data.hpp"

#include <algorithm>
#include <cstring>
#include <limits>

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
      outputs_(&config.outputs()),
      inputs_(&config.inputs()),
      buffer_(std::max(config.max_bytes(PdoDirection::Rx), config.max_bytes(PdoDirection::Tx))) {
  // Room for all of them first: no reallocation leaves a hole in the heap
  // between this slave's objects.
  sms_.reserve(static_cast<std::size_t>(
      std::count_if(config.sms().begin(), config.sms().end(), [](const SmLayout& sm) { return sm.checked; })));
  for (const PdoDirection d : {PdoDirection::Rx, PdoDirection::Tx}) {
    for (const SmLayout& sm : config.sms()) {
      if (sm.direction != d || !sm.checked) continue;
      SmCopy& c = sms_.emplace_back();
      c.image = &sm.image;
      c.sm = sm.sm;
      c.copies.reserve(sm.image.capacity());
    }
    if (d == PdoDirection::Rx) rx_count_ = sms_.size();
  }
  config.count_rebuilds_in(&rebuilds_);
}

void ProcessData::refresh() noexcept {
  for (SmCopy& c : sms_) {
    if (c.generation != c.image->generation()) rebuild(c);
  }
  output_items_ = outputs_->items();
  rebuilds_seen_ = rebuilds_;
}

void ProcessData::rebuild(SmCopy& p) noexcept {
  const ProcessDataImage& image = *p.image;
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
    // A byte copy whose SM bytes and value bytes both follow the previous
    // one's joins it: the object store lays the default mapping's values
    // out in image order (ObjectStore), so a default image is a few blocks.
    if (c.bytes != 0 && !p.copies.empty()) {
      Copy& last = p.copies.back();
      if (last.bytes != 0 && last.at + last.bytes == c.at && last.value + last.bytes == c.value &&
          last.bytes + c.bytes <= std::numeric_limits<std::uint16_t>::max()) {
        last.bytes = static_cast<std::uint16_t>(last.bytes + c.bytes);
        continue;
      }
    }
    p.copies.push_back(c);  // within the reserved capacity: the image holds at most that many
  }
  p.covered = contiguous ? covered : 0;
  p.byte_length = image.byte_length();
  p.generation = image.generation();
}

ProcessData::SmArea ProcessData::area(esc::Pdi& pdi, const SmCopy& c) noexcept {
  if (layout_loaded_) return c.area;
  std::uint8_t raw[esc::reg::kSyncManagerStride]{};
  pdi.read(esc::reg::sync_manager(c.sm), raw);
  return {load_le<std::uint16_t>(raw + esc::reg::sm::kStartAddress), load_le<std::uint16_t>(raw + esc::reg::sm::kLength),
          (raw[esc::reg::sm::kActivate] & bits::kSmActivateEnable) != 0};
}

void ProcessData::load_layout(esc::Pdi& pdi) noexcept {
  layout_loaded_ = false;
  for (SmCopy& c : sms_) c.area = area(pdi, c);
  layout_loaded_ = true;
}

void ProcessData::read_outputs(esc::Pdi& pdi) noexcept {
  refresh_plans();
  for (std::size_t k = 0; k < rx_count_; ++k) read_sm(pdi, sms_[k]);
}

void ProcessData::write_inputs(esc::Pdi& pdi) noexcept {
  refresh_plans();
  for (std::size_t k = rx_count_; k < sms_.size(); ++k) write_sm(pdi, sms_[k]);
}

// The plans are current (refresh_plans): the image itself is read only for
// an item copied bit by bit.
void ProcessData::read_sm(esc::Pdi& pdi, SmCopy& c) noexcept {
  const SmArea sm = area(pdi, c);
  if (!sm.enabled || sm.length == 0 || sm.length > buffer_.size() || sm.length < c.byte_length) return;
  // In place where the PDI can (the ESC's 3-buffer), else through buffer_.
  const std::uint8_t* buffer = pdi.read_buffer(sm.start, {buffer_.data(), sm.length}).data();
  for (const Copy& k : c.copies) {
    if (k.bytes != 0) {
      esc::copy_small(k.value, buffer + k.at, k.bytes);
    } else {
      const PdoItem& item = c.image->items()[k.at];
      get_bits(k.value, buffer, item.bit_position(), item.bits);
    }
  }
}

void ProcessData::write_sm(esc::Pdi& pdi, SmCopy& c) noexcept {
  const SmArea sm = area(pdi, c);
  if (!sm.enabled || sm.length == 0 || sm.length > buffer_.size() || sm.length < c.byte_length) return;
  const SmCopy& p = c;
  const std::span<std::uint8_t> place = pdi.write_buffer_begin(sm.start, {buffer_.data(), sm.length});
  std::uint8_t* buffer = place.data();
  // Bytes no copy writes are 0 (gaps, padding, the rest of a longer SM).
  if (p.covered != sm.length) std::memset(buffer, 0, place.size());
  for (const Copy& k : p.copies) {
    if (k.bytes != 0) {
      esc::copy_small(buffer + k.at, k.value, k.bytes);
    } else {
      const PdoItem& item = c.image->items()[k.at];
      put_bits(buffer, item.bit_position(), k.value, item.bits);
    }
  }
  pdi.write_buffer_commit(sm.start, place);
}

}  // namespace ecat::coe
