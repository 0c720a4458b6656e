// Walks the datagrams of an EtherCAT frame in place (ETG.1000.4 §5.3/§5.4).
// parse_frame() checks every bound once — Ethernet header, frame header
// length, each datagram's header, data and WKC, the "more" chain — and
// returns a small view (buffer, where the datagrams start, how many): no
// table, nothing copied, no heap. After that, DatagramView reads and writes
// fields of a datagram directly in the caller's buffer without further
// checks, and the datagrams are walked in place: each one's 11-bit length
// says where the next starts (an ESC never changes a length).
#pragma once

#include <cstddef>
#include <cstdint>
#include <iterator>

#include "common/frame.hpp"

namespace ecat {

// A datagram inside a validated frame buffer: header, data and WKC are in
// bounds (guaranteed by parse_frame). Field offsets per ETG.1000.4 §5.4.1.
class DatagramView {
 public:
  static constexpr std::size_t kCmdOffset = 0;
  static constexpr std::size_t kIndexOffset = 1;
  static constexpr std::size_t kAdpOffset = 2;
  static constexpr std::size_t kAdoOffset = 4;
  static constexpr std::size_t kLengthOffset = 6;
  static constexpr std::size_t kIrqOffset = 8;

  constexpr DatagramView() noexcept = default;
  constexpr explicit DatagramView(std::uint8_t* header) noexcept : p_(header) {}

  Command command() const noexcept { return static_cast<Command>(p_[kCmdOffset]); }
  std::uint8_t index() const noexcept { return p_[kIndexOffset]; }
  std::uint16_t adp() const noexcept { return load_le<std::uint16_t>(p_ + kAdpOffset); }
  void set_adp(std::uint16_t v) noexcept { store_le(p_ + kAdpOffset, v); }
  std::uint16_t ado() const noexcept { return load_le<std::uint16_t>(p_ + kAdoOffset); }
  std::uint32_t logical_address() const noexcept { return load_le<std::uint32_t>(p_ + kAdpOffset); }
  std::uint16_t length() const noexcept {
    return static_cast<std::uint16_t>(length_word() & kDatagramLengthMask);
  }
  bool circulating() const noexcept { return (length_word() & kDatagramCirculating) != 0; }
  void set_circulating(bool c) noexcept {
    std::uint16_t w = length_word();
    w = static_cast<std::uint16_t>(c ? (w | kDatagramCirculating) : (w & ~kDatagramCirculating));
    store_le(p_ + kLengthOffset, w);
  }
  bool more() const noexcept { return (length_word() & kDatagramMore) != 0; }
  std::uint16_t irq() const noexcept { return load_le<std::uint16_t>(p_ + kIrqOffset); }
  void set_irq(std::uint16_t v) noexcept { store_le(p_ + kIrqOffset, v); }
  Bytes data() const noexcept { return Bytes(p_ + kDatagramHeaderSize, length()); }
  std::uint16_t wkc() const noexcept { return load_le<std::uint16_t>(wkc_ptr()); }
  void set_wkc(std::uint16_t v) noexcept { store_le(wkc_ptr(), v); }
  // Adds to the WKC, wrapping at 16 bits as on silicon.
  void add_wkc(std::uint16_t n) noexcept { set_wkc(static_cast<std::uint16_t>(wkc() + n)); }

  DatagramHeader header() const noexcept {
    DatagramHeader h;
    h.command = command();
    h.index = index();
    h.address = logical_address();
    h.length = length();
    h.circulating = circulating();
    h.more = more();
    h.irq = irq();
    return h;
  }
  // Bytes of the whole datagram (header + data + WKC).
  std::size_t wire_size() const noexcept { return kDatagramOverhead + length(); }
  // The datagram after this one (only meaningful when more() is set).
  DatagramView next() const noexcept { return DatagramView(p_ + wire_size()); }
  std::uint8_t* header_pointer() const noexcept { return p_; }

  friend bool operator==(const DatagramView&, const DatagramView&) = default;

 private:
  std::uint16_t length_word() const noexcept { return load_le<std::uint16_t>(p_ + kLengthOffset); }
  std::uint8_t* wkc_ptr() const noexcept { return p_ + kDatagramHeaderSize + length(); }
  std::uint8_t* p_ = nullptr;
};

// A validated frame: where its EtherCAT part starts and how many datagrams
// it carries. Iterate it (for (DatagramView d : frame)) to walk the
// datagrams in place; operator[] walks from the first one (O(i)).
class FrameView {
 public:
  class Iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = DatagramView;
    using difference_type = std::ptrdiff_t;
    using pointer = void;
    using reference = DatagramView;

    Iterator() noexcept = default;
    Iterator(DatagramView d, std::size_t left) noexcept : d_(d), left_(left) {}
    DatagramView operator*() const noexcept { return d_; }
    Iterator& operator++() noexcept {
      if (--left_ != 0) d_ = d_.next();
      return *this;
    }
    Iterator operator++(int) noexcept {
      Iterator old = *this;
      ++*this;
      return old;
    }
    // Iterators of one frame compare by how many datagrams are left.
    friend bool operator==(const Iterator& a, const Iterator& b) noexcept { return a.left_ == b.left_; }

   private:
    DatagramView d_;
    std::size_t left_ = 0;
  };

  Bytes frame() const noexcept { return frame_; }
  std::size_t ethercat_offset() const noexcept { return ecat_offset_; }
  const FrameHeader& header() const noexcept { return header_; }
  std::size_t size() const noexcept { return count_; }
  bool empty() const noexcept { return count_ == 0; }
  DatagramView front() const noexcept { return DatagramView(frame_.data() + first_offset()); }
  Iterator begin() const noexcept { return count_ == 0 ? end() : Iterator(front(), count_); }
  Iterator end() const noexcept { return Iterator(DatagramView(), 0); }
  DatagramView operator[](std::size_t i) const noexcept {
    DatagramView d = front();
    for (; i != 0; --i) d = d.next();
    return d;
  }
  // Offset of datagram i's header from the start of the buffer.
  std::size_t offset(std::size_t i) const noexcept {
    return static_cast<std::size_t>((*this)[i].header_pointer() - frame_.data());
  }

  template <typename F>
  void for_each(F&& f) const {
    for (DatagramView d : *this) f(d);
  }

 private:
  friend Expected<FrameView, FrameError> parse_ethercat(Bytes buffer, std::size_t ecat_offset) noexcept;
  std::size_t first_offset() const noexcept { return ecat_offset_ + kFrameHeaderSize; }
  Bytes frame_;
  std::size_t ecat_offset_ = 0;
  FrameHeader header_{};
  std::size_t count_ = 0;
};

// The datagrams of the EtherCAT part starting at `ecat_offset` (the frame
// header) of `buffer`, every bound checked: where the first one starts and
// how many there are (count 0: malformed, `error` says why). The one set
// of rules behind parse_ethercat, and what esc::Segment walks without
// building a FrameView.
struct ValidatedDatagrams {
  std::uint8_t* first = nullptr;
  std::size_t count = 0;
  FrameError error = FrameError::TooShort;
};

inline ValidatedDatagrams validate_ethercat(Bytes buffer, std::size_t ecat_offset) noexcept {
  if (ecat_offset > buffer.size() || buffer.size() - ecat_offset < kFrameHeaderSize) {
    return {nullptr, 0, FrameError::TooShort};
  }
  const FrameHeader header = FrameHeader::decode(load_le<std::uint16_t>(buffer.data() + ecat_offset));
  if (header.type != kFrameTypeDlpdu) return {nullptr, 0, FrameError::UnsupportedType};
  std::uint8_t* const first = buffer.data() + ecat_offset + kFrameHeaderSize;
  std::size_t left = header.length;  // bytes from the current datagram to the end
  if (left > buffer.size() - ecat_offset - kFrameHeaderSize) return {nullptr, 0, FrameError::LengthBeyondFrame};
  if (left < kDatagramOverhead) return {nullptr, 0, FrameError::TooShort};
  // The common cyclic frame, one datagram: the loop below unrolled once
  // (same checks in the same order).
  const std::uint16_t word0 = load_le<std::uint16_t>(first + DatagramView::kLengthOffset);
  if ((word0 & kDatagramMore) == 0) {
    if (!is_known_command(first[DatagramView::kCmdOffset])) return {nullptr, 0, FrameError::UnknownCommand};
    const std::size_t total = kDatagramOverhead + (word0 & kDatagramLengthMask);
    if (left < total) return {nullptr, 0, FrameError::DatagramBeyondFrame};
    if (left != total) return {nullptr, 0, FrameError::LengthMismatch};
    return {first, 1, FrameError::TooShort};
  }
  const std::uint8_t* h = first;
  std::size_t count = 0;
  for (;;) {
    if (left < kDatagramOverhead) return {nullptr, 0, FrameError::DatagramBeyondFrame};
    if (!is_known_command(h[DatagramView::kCmdOffset])) return {nullptr, 0, FrameError::UnknownCommand};
    const std::uint16_t word = load_le<std::uint16_t>(h + DatagramView::kLengthOffset);
    const std::size_t total = kDatagramOverhead + (word & kDatagramLengthMask);
    if (left < total) return {nullptr, 0, FrameError::DatagramBeyondFrame};
    if (count == kMaxDatagramsPerFrame) return {nullptr, 0, FrameError::TooManyDatagrams};
    ++count;
    h += total;
    left -= total;
    if ((word & kDatagramMore) == 0) break;
  }
  if (left != 0) return {nullptr, 0, FrameError::LengthMismatch};
  return {first, count, FrameError::TooShort};
}

// Parses the EtherCAT part starting at `ecat_offset` (the frame header) of
// `buffer`. Used directly for EtherCAT carried in UDP (ecat_offset 0).
inline Expected<FrameView, FrameError> parse_ethercat(Bytes buffer, std::size_t ecat_offset) noexcept {
  const ValidatedDatagrams d = validate_ethercat(buffer, ecat_offset);
  if (d.count == 0) return fail(d.error);
  FrameView v;
  v.frame_ = buffer;
  v.ecat_offset_ = ecat_offset;
  v.header_ = FrameHeader::decode(load_le<std::uint16_t>(buffer.data() + ecat_offset));
  v.count_ = d.count;
  return v;
}

namespace detail {
// Where the EtherCAT frame header starts in an Ethernet frame (EtherType
// 0x88A4, optionally behind one 802.1Q tag; both big-endian on the wire,
// IEEE 802.3), read in place. `error` is meaningful when !ok.
struct EthercatAt {
  bool ok = false;
  FrameError error = FrameError::TooShort;
  std::size_t offset = 0;
};
constexpr EthercatAt find_ethercat(ConstBytes frame) noexcept {
  constexpr std::size_t kTypeOffset = 2 * kMacSize;
  if (frame.size() < kEthernetHeaderSize) return {false, FrameError::TooShort, 0};
  std::size_t at = kTypeOffset;
  auto type = static_cast<std::uint16_t>((frame[at] << 8) | frame[at + 1]);
  if (type == kEtherTypeVlan) {
    if (frame.size() < kEthernetHeaderSize + kVlanTagSize) return {false, FrameError::TooShort, 0};
    at += kVlanTagSize;
    type = static_cast<std::uint16_t>((frame[at] << 8) | frame[at + 1]);
  }
  if (type != kEtherTypeEtherCat) return {false, FrameError::NotEtherCat, 0};
  return {true, FrameError::TooShort, at + sizeof(std::uint16_t)};
}
}  // namespace detail

// Offset of the EtherCAT frame header in an Ethernet frame carrying EtherCAT.
inline Expected<std::size_t, FrameError> locate_ethercat(ConstBytes frame) noexcept {
  const detail::EthercatAt at = detail::find_ethercat(frame);
  if (!at.ok) return fail(at.error);
  return at.offset;
}

// Parses an Ethernet frame carrying EtherCAT. Bytes after the EtherCAT
// length are padding.
inline Expected<FrameView, FrameError> parse_frame(Bytes frame) noexcept {
  const detail::EthercatAt at = detail::find_ethercat(frame);
  if (!at.ok) return fail(at.error);
  return parse_ethercat(frame, at.offset);
}

}  // namespace ecat
