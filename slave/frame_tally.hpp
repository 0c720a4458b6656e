// Datagram count and WKC sum of a returned frame for ChainStats, and the
// address of its first logical datagram for CycleTiming, by a light
// walk over the datagram headers (ETG.1000.4 §5.3: 10-byte header with the
// length in bits 10:0 and "more follows" in bit 15 of bytes 6-7, data, WKC).
// The frame was parsed and checked on its way in, so this only stops at the
// end of the buffer and never re-validates.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>

#include "common/command.hpp"
#include "common/frame.hpp"
#include "common/le.hpp"

namespace ecat::slave {

struct FrameTally {
  std::uint32_t datagrams = 0;
  std::uint64_t wkc_total = 0;
  bool logical = false;             // it carries an LRD, LWR or LRW
  std::uint32_t first_logical = 0;  // the logical address of the first of them
};

namespace tally_detail {
inline constexpr std::size_t kEtherTypeOffset = 2 * kMacSize;
inline constexpr std::size_t kDatagramLengthOffset = 6;  // bytes 6-7 of the datagram header
inline constexpr std::size_t kDatagramAddressOffset = 2;  // bytes 2-5: the logical address of LRD/LWR/LRW
inline constexpr auto kFirstLogical = static_cast<std::uint8_t>(Command::Lrd);
inline constexpr auto kLogicalSpan = static_cast<std::uint8_t>(static_cast<std::uint8_t>(Command::Lrw) - kFirstLogical);
static_assert(static_cast<std::uint8_t>(Command::Lwr) == kFirstLogical + 1 && kLogicalSpan == 2);
inline std::uint16_t be16(std::span<const std::uint8_t> f, std::size_t pos) noexcept {
  return static_cast<std::uint16_t>((f[pos] << 8) | f[pos + 1]);
}
}  // namespace tally_detail

inline FrameTally tally_frame(std::span<const std::uint8_t> frame) noexcept {
  using namespace tally_detail;
  FrameTally t;
  // EtherType 0x88A4, optionally behind one 802.1Q tag (IEEE 802.3, big-endian).
  if (frame.size() < kEthernetHeaderSize + kVlanTagSize + kFrameHeaderSize) return t;
  std::size_t at = kEtherTypeOffset;
  if (be16(frame, at) == kEtherTypeVlan) at += kVlanTagSize;
  if (be16(frame, at) != kEtherTypeEtherCat) return t;
  at += sizeof(std::uint16_t);
  std::size_t pos = at + kFrameHeaderSize;
  const std::size_t length = load_le<std::uint16_t>(frame.data() + at) & kFrameLengthMask;
  const std::size_t end = std::min(frame.size(), pos + length);
  while (end - pos >= kDatagramOverhead) {
    const std::uint16_t word = load_le<std::uint16_t>(frame.data() + pos + kDatagramLengthOffset);
    const std::size_t data = word & kDatagramLengthMask;
    if (end - pos < kDatagramOverhead + data) break;
    ++t.datagrams;
    // LRD, LWR and LRW are the commands 10-12 (common/command.hpp): one compare.
    if (static_cast<std::uint8_t>(frame[pos] - kFirstLogical) <= kLogicalSpan && !t.logical) {
      t.logical = true;
      t.first_logical = load_le<std::uint32_t>(frame.data() + pos + kDatagramAddressOffset);
    }
    t.wkc_total += load_le<std::uint16_t>(frame.data() + pos + kDatagramHeaderSize + data);
    pos += kDatagramOverhead + data;
    if ((word & kDatagramMore) == 0) break;
  }
  return t;
}

}  // namespace ecat::slave
