// Datagram count and WKC sum of a returned frame for ChainStats, by a light
// walk over the datagram headers (ETG.1000.4 §5.3: 10-byte header with the
// length in bits 10:0 and "more follows" in bit 15 of bytes 6-7, data, WKC).
// The frame was parsed and checked on its way in, so this only stops at the
// end of the buffer and never re-validates.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>

#include "common/frame.hpp"
#include "common/frame_parser.hpp"
#include "common/le.hpp"

namespace ecat::slave {

struct FrameTally {
  std::uint32_t datagrams = 0;
  std::uint64_t wkc_total = 0;
};

inline FrameTally tally_frame(std::span<const std::uint8_t> frame) noexcept {
  FrameTally t;
  const auto at = locate_ethercat(frame);
  if (!at || frame.size() - *at < kFrameHeaderSize) return t;
  std::size_t pos = *at + kFrameHeaderSize;
  const std::size_t length = load_le<std::uint16_t>(frame.data() + *at) & kFrameLengthMask;
  const std::size_t end = std::min(frame.size(), pos + length);
  while (end - pos >= kDatagramOverhead) {
    const std::uint16_t word = load_le<std::uint16_t>(frame.data() + pos + DatagramView::kLengthOffset);
    const std::size_t data = word & kDatagramLengthMask;
    if (end - pos < kDatagramOverhead + data) break;
    ++t.datagrams;
    t.wkc_total += load_le<std::uint16_t>(frame.data() + pos + kDatagramHeaderSize + data);
    pos += kDatagramOverhead + data;
    if ((word & kDatagramMore) == 0) break;
  }
  return t;
}

}  // namespace ecat::slave
