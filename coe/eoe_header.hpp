// The 4-byte EoE header in front of every EoE mailbox payload (ETG.1000.6
// §5.7 EoE; shared/spec/coe-mailbox.md §1 type 2; field layout as SOEM's
// ec_eoe.h reads it). Two little-endian words:
//   word 0: frame type (bits 0-3), port (4-7), last fragment (8), time
//           appended (9), time request (10), reserved (11-15);
//   word 1: fragment number (0-5), offset in 32-byte units (6-11; in
//           fragment 0 the complete frame size, rounded up, in 32-byte
//           units), frame number (12-15).
// In the response frame types word 1 is the result code instead.
#pragma once

#include <cstdint>
#include <optional>

#include "common/le.hpp"

namespace ecat::coe::eoe {

inline constexpr std::size_t kHeaderSize = 4;
inline constexpr std::size_t kBlock = 32;  // unit of offset and complete size

enum class FrameType : std::uint8_t {
  FragmentData = 0,
  TimestampResponse = 1,   // "init response timestamp": a timestamp for a sent frame
  SetIpRequest = 2,        // "init request" in ETG.1000.6
  SetIpResponse = 3,
  SetAddressFilterRequest = 4,
  SetAddressFilterResponse = 5,
  GetIpRequest = 6,
  GetIpResponse = 7,
  GetAddressFilterRequest = 8,
  GetAddressFilterResponse = 9,
};

// Result codes of the response frame types (ETG.1000.6 EoE result parameter).
enum class Result : std::uint16_t {
  Success = 0x0000,
  UnspecifiedError = 0x0001,
  UnsupportedFrameType = 0x0002,
  NoIpSupport = 0x0201,
  NoDhcpSupport = 0x0202,
  NoFilterSupport = 0x0401,
};

inline constexpr std::uint16_t kTypeMask = 0x000F;
inline constexpr unsigned kPortShift = 4;
inline constexpr std::uint16_t kPortMask = 0x000F;
inline constexpr std::uint16_t kLastFragment = 1u << 8;
inline constexpr std::uint16_t kTimeAppended = 1u << 9;
inline constexpr std::uint16_t kTimeRequest = 1u << 10;
inline constexpr std::uint16_t kFragmentMask = 0x003F;
inline constexpr unsigned kOffsetShift = 6;
inline constexpr std::uint16_t kOffsetMask = 0x003F;
inline constexpr unsigned kFrameShift = 12;
inline constexpr std::uint16_t kFrameMask = 0x000F;
inline constexpr std::size_t kTimestampSize = 4;  // appended after the last fragment's data

struct Header {
  std::uint8_t type = 0;  // FrameType value (raw: unknown types are kept)
  std::uint8_t port = 0;
  bool last_fragment = false;
  bool time_appended = false;
  bool time_request = false;
  std::uint8_t fragment = 0;
  std::uint8_t offset = 0;  // 32-byte units; complete size in fragment 0
  std::uint8_t frame = 0;

  // Word 1 as a result code (response frame types).
  std::uint16_t result() const noexcept {
    return static_cast<std::uint16_t>(fragment | (offset << kOffsetShift) | (frame << kFrameShift));
  }

  static std::optional<Header> unpack(ConstBytes in) noexcept {
    if (in.size() < kHeaderSize) return std::nullopt;
    const auto w0 = load_le<std::uint16_t>(in.data());
    const auto w1 = load_le<std::uint16_t>(in.data() + 2);
    Header h;
    h.type = static_cast<std::uint8_t>(w0 & kTypeMask);
    h.port = static_cast<std::uint8_t>((w0 >> kPortShift) & kPortMask);
    h.last_fragment = (w0 & kLastFragment) != 0;
    h.time_appended = (w0 & kTimeAppended) != 0;
    h.time_request = (w0 & kTimeRequest) != 0;
    h.fragment = static_cast<std::uint8_t>(w1 & kFragmentMask);
    h.offset = static_cast<std::uint8_t>((w1 >> kOffsetShift) & kOffsetMask);
    h.frame = static_cast<std::uint8_t>((w1 >> kFrameShift) & kFrameMask);
    return h;
  }

  static std::uint16_t word0(std::uint8_t type, std::uint8_t port, bool last) noexcept {
    return static_cast<std::uint16_t>((type & kTypeMask) | ((port & kPortMask) << kPortShift) |
                                      (last ? kLastFragment : 0));
  }
  static std::uint16_t word1(std::uint8_t fragment, std::uint8_t offset, std::uint8_t frame) noexcept {
    return static_cast<std::uint16_t>((fragment & kFragmentMask) | ((offset & kOffsetMask) << kOffsetShift) |
                                      ((frame & kFrameMask) << kFrameShift));
  }
};

}  // namespace ecat::coe::eoe
