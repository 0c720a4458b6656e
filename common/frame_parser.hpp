// Walks the datagrams of an EtherCAT frame in place (ETG.1000.4 §5.3/§5.4).
// parse_frame() checks every bound once — Ethernet header, frame header
// length, each datagram's header, data and WKC, the "more" chain — and
// records where each datagram starts in a fixed-capacity table (no heap).
// After that, DatagramView reads and writes fields of a datagram directly in
// the caller's buffer without further checks.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>

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

 private:
  std::uint16_t length_word() const noexcept { return load_le<std::uint16_t>(p_ + kLengthOffset); }
  std::uint8_t* wkc_ptr() const noexcept { return p_ + kDatagramHeaderSize + length(); }
  std::uint8_t* p_ = nullptr;
};

// A validated frame: where its EtherCAT part starts and where each datagram is.
class FrameView {
 public:
  Bytes frame() const noexcept { return frame_; }
  std::size_t ethercat_offset() const noexcept { return ecat_offset_; }
  const FrameHeader& header() const noexcept { return header_; }
  std::size_t size() const noexcept { return count_; }
  bool empty() const noexcept { return count_ == 0; }
  DatagramView operator[](std::size_t i) const noexcept {
    return DatagramView(frame_.data() + offsets_[i]);
  }
  // Offset of datagram i's header from the start of the buffer.
  std::size_t offset(std::size_t i) const noexcept { return offsets_[i]; }

  template <typename F>
  void for_each(F&& f) const {
    for (std::size_t i = 0; i < count_; ++i) f((*this)[i]);
  }

 private:
  friend Expected<FrameView, FrameError> parse_ethercat(Bytes buffer, std::size_t ecat_offset) noexcept;
  Bytes frame_;
  std::size_t ecat_offset_ = 0;
  FrameHeader header_{};
  std::size_t count_ = 0;
  std::array<std::uint32_t, kMaxDatagramsPerFrame> offsets_{};
};

// Parses the EtherCAT part starting at `ecat_offset` (the frame header) of
// `buffer`. Used directly for EtherCAT carried in UDP (ecat_offset 0).
inline Expected<FrameView, FrameError> parse_ethercat(Bytes buffer, std::size_t ecat_offset) noexcept {
  if (ecat_offset > buffer.size() || buffer.size() - ecat_offset < kFrameHeaderSize) {
    return fail(FrameError::TooShort);
  }
  FrameView v;
  v.frame_ = buffer;
  v.ecat_offset_ = ecat_offset;
  v.header_ = FrameHeader::decode(load_le<std::uint16_t>(buffer.data() + ecat_offset));
  if (v.header_.type != kFrameTypeDlpdu) return fail(FrameError::UnsupportedType);
  std::size_t pos = ecat_offset + kFrameHeaderSize;
  const std::size_t end = pos + v.header_.length;
  if (end > buffer.size()) return fail(FrameError::LengthBeyondFrame);
  if (v.header_.length < kDatagramOverhead) return fail(FrameError::TooShort);
  for (;;) {
    if (end - pos < kDatagramOverhead) return fail(FrameError::DatagramBeyondFrame);
    const std::uint8_t* h = buffer.data() + pos;
    if (!is_known_command(h[DatagramView::kCmdOffset])) return fail(FrameError::UnknownCommand);
    const std::uint16_t word = load_le<std::uint16_t>(h + DatagramView::kLengthOffset);
    const std::size_t total = kDatagramOverhead + (word & kDatagramLengthMask);
    if (end - pos < total) return fail(FrameError::DatagramBeyondFrame);
    if (v.count_ == kMaxDatagramsPerFrame) return fail(FrameError::TooManyDatagrams);
    v.offsets_[v.count_++] = static_cast<std::uint32_t>(pos);
    pos += total;
    if ((word & kDatagramMore) == 0) break;
  }
  if (pos != end) return fail(FrameError::LengthMismatch);
  return v;
}

// Parses an Ethernet frame carrying EtherCAT (EtherType 0x88A4, optionally
// behind one VLAN tag). Bytes after the EtherCAT length are padding.
inline Expected<FrameView, FrameError> parse_frame(Bytes frame) noexcept {
  auto eth = EthernetHeader::unpack(frame);
  if (!eth) return fail(eth.error());
  if (eth->ether_type != kEtherTypeEtherCat) return fail(FrameError::NotEtherCat);
  return parse_ethercat(frame, eth->size());
}

}  // namespace ecat
