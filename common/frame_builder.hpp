// Builds an EtherCAT frame into a caller-provided buffer (no heap): Ethernet
// header, EtherCAT frame header (type 1), then datagrams appended one by one.
// Each append sets the previous datagram's "more follows" bit and updates the
// frame length (ETG.1000.4 §5.3/§5.4). finish() pads to the 60-byte Ethernet
// minimum; padding is not counted in the EtherCAT length.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "common/frame.hpp"
#include "common/frame_parser.hpp"

namespace ecat {

class FrameBuilder {
 public:
  // `buffer` must outlive the builder; it should hold at least
  // kMinEthernetFrame bytes so finish() can pad.
  explicit FrameBuilder(Bytes buffer, const MacAddress& destination = kBroadcastMac,
                        const MacAddress& source = MacAddress{}) noexcept
      : buf_(buffer) {
    EthernetHeader eth;
    eth.destination = destination;
    eth.source = source;
    ok_ = eth.pack(buf_) && buf_.size() >= eth.size() + kFrameHeaderSize;
    ecat_offset_ = eth.size();
    pos_ = ecat_offset_ + kFrameHeaderSize;
    write_frame_header();
  }

  // Appends a datagram whose data is a copy of `data`; the WKC starts at 0.
  // Returns the datagram's header offset in the buffer.
  Expected<std::size_t, FrameError> append(Command command, std::uint8_t index, std::uint32_t address,
                                           ConstBytes data, std::uint16_t irq = 0) noexcept {
    auto at = reserve(command, index, address, data.size(), irq);
    if (at && !data.empty()) std::memcpy(buf_.data() + *at + kDatagramHeaderSize, data.data(), data.size());
    return at;
  }

  // Appends a datagram with `length` zero data bytes (for reads).
  Expected<std::size_t, FrameError> append_zeros(Command command, std::uint8_t index, std::uint32_t address,
                                                 std::uint16_t length, std::uint16_t irq = 0) noexcept {
    return reserve(command, index, address, length, irq);
  }

  // Data bytes a further datagram could carry (0 if not even a header fits).
  std::size_t remaining_data_capacity() const noexcept {
    if (!ok_ || limit() < pos_ + kDatagramOverhead) return 0;
    return std::min(limit() - pos_ - kDatagramOverhead, kMaxDatagramData);
  }

  std::size_t datagram_count() const noexcept { return count_; }
  bool ok() const noexcept { return ok_; }
  std::size_t ethercat_offset() const noexcept { return ecat_offset_; }

  // The frame: header, datagrams, and zero padding up to 60 bytes if the
  // buffer allows. Empty if the buffer could not even hold the headers.
  Bytes finish() noexcept {
    if (!ok_) return {};
    std::size_t size = pos_;
    if (size < kMinEthernetFrame && buf_.size() >= kMinEthernetFrame) {
      std::memset(buf_.data() + size, 0, kMinEthernetFrame - size);
      size = kMinEthernetFrame;
    }
    return buf_.first(size);
  }

  // A view of the datagram appended at header offset `at` (as returned by append).
  DatagramView datagram_at(std::size_t at) const noexcept { return DatagramView(buf_.data() + at); }

 private:
  Expected<std::size_t, FrameError> reserve(Command command, std::uint8_t index, std::uint32_t address,
                                            std::size_t length, std::uint16_t irq) noexcept {
    if (!ok_ || length > kMaxDatagramData || count_ == kMaxDatagramsPerFrame ||
        limit() < pos_ + kDatagramOverhead + length) {
      return fail(FrameError::BufferFull);
    }
    if (count_ > 0) {
      std::uint8_t* word = buf_.data() + last_ + DatagramView::kLengthOffset;
      store_le(word, static_cast<std::uint16_t>(load_le<std::uint16_t>(word) | kDatagramMore));
    }
    DatagramHeader h;
    h.command = command;
    h.index = index;
    h.address = address;
    h.length = static_cast<std::uint16_t>(length);
    h.irq = irq;
    const std::size_t at = pos_;
    h.pack(buf_.subspan(at, kDatagramHeaderSize));
    std::memset(buf_.data() + at + kDatagramHeaderSize, 0, length + kWkcSize);
    pos_ += kDatagramOverhead + length;
    last_ = at;
    ++count_;
    write_frame_header();
    return at;
  }

  // End of the usable buffer: its size, or what an 11-bit EtherCAT length allows.
  std::size_t limit() const noexcept {
    return std::min(buf_.size(), ecat_offset_ + kFrameHeaderSize + kFrameLengthMask);
  }

  void write_frame_header() noexcept {
    if (!ok_) return;
    FrameHeader fh;
    fh.length = static_cast<std::uint16_t>(pos_ - ecat_offset_ - kFrameHeaderSize);
    fh.type = kFrameTypeDlpdu;
    fh.pack(buf_.subspan(ecat_offset_));
  }

  Bytes buf_;
  bool ok_ = false;
  std::size_t ecat_offset_ = 0;
  std::size_t pos_ = 0;
  std::size_t last_ = 0;
  std::size_t count_ = 0;
};

}  // namespace ecat
