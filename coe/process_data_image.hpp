// Layout of one direction of process data (ETG.1000.6 §5.6.7.4.7): the mapped
// entries of the assigned PDOs, in assignment then mapping order, packed
// bit-wise without gaps between PDOs. Recomputed when the mapping or the
// assignment changes (set-up path); its item table has a fixed capacity.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "coe/object_store.hpp"

namespace ecat::coe {

struct PdoItem {
  std::uint32_t byte_offset = 0;
  std::uint8_t bit_offset = 0;  // 0..7 inside byte_offset
  std::uint16_t bits = 0;
  ObjectStore::Slot* entry = nullptr;  // null for a gap
  std::uint32_t bit_position() const noexcept { return byte_offset * 8u + bit_offset; }
};

class ProcessDataImage {
 public:
  explicit ProcessDataImage(std::size_t capacity = 0) : capacity_(capacity) { items_.reserve(capacity); }

  void clear() noexcept {
    items_.clear();
    bits_ = 0;
    ++generation_;
  }
  // False (and nothing added) when the capacity is reached.
  bool add(std::uint16_t bits, ObjectStore::Slot* entry) noexcept {
    if (items_.size() == capacity_) return false;
    items_.push_back({bits_ / 8u, static_cast<std::uint8_t>(bits_ % 8u), bits, entry});
    bits_ += bits;
    ++generation_;
    return true;
  }
  std::span<const PdoItem> items() const noexcept { return items_; }
  std::uint32_t bit_length() const noexcept { return bits_; }
  std::uint32_t byte_length() const noexcept { return (bits_ + 7u) / 8u; }
  std::size_t capacity() const noexcept { return capacity_; }
  // Changes with every clear()/add(): a copy plan made from the items stays
  // valid while it is the same (coe::ProcessData).
  std::uint64_t generation() const noexcept { return generation_; }

 private:
  std::vector<PdoItem> items_;
  std::size_t capacity_ = 0;
  std::uint32_t bits_ = 0;
  std::uint64_t generation_ = 0;
};

}  // namespace ecat::coe
