// Live values of every entry of an object dictionary (CiA 301 §7.4): one
// contiguous byte buffer sized at construction (no heap afterwards), found by
// binary search on (index, subindex). The od::Dictionary it was built from is
// the description and must outlive the store.
//
// Two kinds of access:
//  - application side (get/set/assign): no access rights, no hooks; used by
//    the drive, the PDO copy and the parameter file;
//  - service side (read/write): what the SDO server calls; checks lengths and
//    the dictionary's min/max and runs the per-index ObjectHooks.
// ESM-state access rights are the SDO server's job (it knows the request).
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <type_traits>
#include <vector>

#include "coe/object_hooks.hpp"
#include "coe/recent_log.hpp"
#include "coe/sdo_abort.hpp"
#include "coe/value.hpp"
#include "common/expected.hpp"
#include "common/le.hpp"
#include "od/dictionary.hpp"

namespace ecat::coe {

class ObjectStore {
 public:
  struct Options {
    // Capacity of string/octet-string/domain entries whose dictionary bit
    // length is 0 ("variable"), in bytes.
    std::uint32_t variable_capacity = 65536;
  };

  // Where one entry's value lives. Stable for the life of the store, so the
  // drive and the PDO image may keep pointers to it.
  // 16 bytes: one per entry and slave, thousands of slaves in a chain
  // (issue 16 item 5; the generic servo's 211 entries were 24 bytes each
  // until issue 30 took its memory under 32 KiB). The object's index is
  // index_of(); a string's current length is kept in the value buffer, in
  // the kLengthPrefix bytes before its value (length()).
  struct Slot {
    const od::Entry* entry = nullptr;
    std::uint32_t offset = 0;  // into the value buffer
    // Bytes reserved (at most Options::variable_capacity, under 2^31), and
    // whether the entry is a string whose length may be less: kept here so
    // that length() does not reach into the description.
    std::uint32_t capacity : 31 = 0;
    std::uint32_t is_string : 1 = 0;
    bool variable() const noexcept { return is_string != 0; }
  };
  static constexpr std::uint32_t kLengthPrefix = sizeof(std::uint32_t);
  static constexpr std::uint32_t kMaxCapacity = (1u << 31) - 1;

  explicit ObjectStore(const od::Dictionary& dictionary) : ObjectStore(dictionary, Options{}) {}
  ObjectStore(const od::Dictionary& dictionary, Options options);
  ObjectStore(const ObjectStore&) = delete;
  ObjectStore& operator=(const ObjectStore&) = delete;

  const od::Dictionary& dictionary() const noexcept { return dictionary_; }

  // Registers hooks for every entry of `index` (start-up only). Null removes them.
  // Returns false if the object does not exist.
  bool set_hooks(std::uint16_t index, ObjectHooks* hooks) noexcept;
  ObjectHooks* hooks(std::uint16_t index) const noexcept;

  const Slot* slot(std::uint16_t index, std::uint8_t subindex) const noexcept;
  Slot* slot(std::uint16_t index, std::uint8_t subindex) noexcept;
  bool contains(std::uint16_t index) const noexcept;

  // Bytes currently valid: the capacity, or a string's length.
  std::uint32_t length(const Slot& s) const noexcept {
    return s.variable() ? load_le<std::uint32_t>(buffer_.data() + s.offset - kLengthPrefix) : s.capacity;
  }
  // The index of the object a slot (one of slots()) belongs to.
  std::uint16_t index_of(const Slot& s) const noexcept;

  // Current bytes of an entry (empty if it does not exist).
  ConstBytes value(const Slot& s) const noexcept { return {buffer_.data() + s.offset, length(s)}; }
  ConstBytes value(std::uint16_t index, std::uint8_t subindex) const noexcept;
  // Writable view of the whole capacity (application-side fast path).
  // Writes through it are not counted in generation(): its users are the
  // cyclic copies (the RxPDO copy, the drive binding), which track their
  // own entries.
  Bytes storage(Slot& s) noexcept { return {buffer_.data() + s.offset, s.capacity}; }
  // The value buffer itself: slot s's bytes begin at values() + s.offset.
  // Stable for the life of the store; for the cyclic copies that keep an
  // entry's offset (4 bytes) instead of a pointer (8) per entry and drive.
  // Writes through it are not counted in generation() either.
  std::uint8_t* values() noexcept { return buffer_.data(); }
  std::size_t value_bytes() const noexcept { return buffer_.size(); }  // values()' length
  // Counts the writes through set/assign/write/reset_to_defaults: a value
  // that did not change since a reader saw the same generation was written by
  // none of them (issue 8: the drive binding copies the unmapped entries
  // again only then).
  std::uint64_t generation() const noexcept { return generation_; }

  // ---- application side -------------------------------------------------
  // Typed read of an integer/real entry (0 if missing). Narrow signed types
  // (INTEGER24 ...) are sign-extended.
  template <typename T>
  T get(std::uint16_t index, std::uint8_t subindex) const noexcept {
    const Slot* s = slot(index, subindex);
    return s ? get<T>(*s) : T{};
  }
  template <typename T>
  T get(const Slot& s) const noexcept {
    static_assert(std::is_arithmetic_v<T>);
    const ConstBytes b{buffer_.data() + s.offset, s.capacity};  // a number's length is its capacity
    if constexpr (std::is_same_v<T, float>) {
      return std::bit_cast<float>(static_cast<std::uint32_t>(load_bits(b, 32, false)));
    } else if constexpr (std::is_same_v<T, double>) {
      return std::bit_cast<double>(load_bits(b, 64, false));
    } else {
      const unsigned bits = static_cast<unsigned>(std::min<std::size_t>(b.size(), 8) * 8);
      return static_cast<T>(load_bits(b, bits, od::is_signed(s.entry->type)));
    }
  }
  // Typed write, no hooks, no range check; fails with 06020000/06090011 if
  // the entry is missing.
  template <typename T>
  Expected<void, SdoAbort> set(std::uint16_t index, std::uint8_t subindex, T v) noexcept {
    Slot* s = slot(index, subindex);
    if (!s) return fail(missing(index));
    set(*s, v);
    return {};
  }
  template <typename T>
  void set(Slot& s, T v) noexcept {
    static_assert(std::is_arithmetic_v<T>);
    std::uint64_t raw = 0;
    if constexpr (std::is_same_v<T, float>) {
      raw = std::bit_cast<std::uint32_t>(v);
    } else if constexpr (std::is_same_v<T, double>) {
      raw = std::bit_cast<std::uint64_t>(v);
    } else {
      raw = static_cast<std::uint64_t>(v);
    }
    std::uint8_t* p = buffer_.data() + s.offset;
    for (std::uint32_t i = 0; i < s.capacity && i < 8; ++i) p[i] = static_cast<std::uint8_t>(raw >> (8 * i));
    ++generation_;
  }
  // Raw write of the wire bytes (no hooks, no range check). Fixed-size entries
  // need exactly their size; variable ones up to their capacity.
  Expected<void, SdoAbort> assign(std::uint16_t index, std::uint8_t subindex, ConstBytes data) noexcept;
  Expected<void, SdoAbort> assign(Slot& s, ConstBytes data) noexcept;

  // Every entry back to its dictionary default.
  void reset_to_defaults() noexcept;

  // ---- service side (SDO) -------------------------------------------------
  // Runs on_read, then copies the value into `out`. Returns the value length.
  Expected<std::size_t, SdoAbort> read(std::uint16_t index, std::uint8_t subindex, Bytes out) noexcept;
  // Checks length (06070010/12/13) and range (06090030/31/32), asks on_write,
  // commits, then after_write. A refused write leaves the value unchanged.
  Expected<void, SdoAbort> write(const WriteRequest& request) noexcept;
  // The checks of write() without committing.
  Expected<void, SdoAbort> check(const Slot& s, ConstBytes data) const noexcept;

  // The entries write() committed (SDO downloads), newest last: what the
  // control interface reports as "sdo_write" events (docs/control.md).
  struct WriteRecord {
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
  };
  static constexpr std::size_t kWriteLogSize = 16;
  const RecentLog<WriteRecord, kWriteLogSize>& service_writes() const noexcept { return service_writes_; }

  // Largest entry capacity, for sizing transfer buffers.
  std::uint32_t max_entry_capacity() const noexcept { return max_capacity_; }
  std::span<const Slot> slots() const noexcept { return slots_; }

 private:
  struct ObjectRange {  // 16 bytes (issue 16 item 5)
    ObjectHooks* hooks = nullptr;
    std::uint32_t first = 0;  // into slots_
    std::uint16_t index = 0;
    std::uint16_t count = 0;  // subindexes 0..255 at most
  };
  const ObjectRange* range(std::uint16_t index) const noexcept;
  std::vector<Slot*> default_image_order();  // set-up only
  SdoAbort missing(std::uint16_t index) const noexcept {
    return contains(index) ? SdoAbort::NoSubindex : SdoAbort::NoObject;
  }
  void load_default(Slot& s) noexcept;

  const od::Dictionary& dictionary_;
  std::vector<std::uint8_t> buffer_;
  std::vector<Slot> slots_;           // sorted by (index, subindex)
  std::vector<ObjectRange> objects_;  // sorted by index
  std::uint32_t max_capacity_ = 0;
  std::uint64_t generation_ = 0;
  RecentLog<WriteRecord, kWriteLogSize> service_writes_;
};

}  // namespace ecat::coe
