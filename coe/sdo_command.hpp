// SDO command byte values (CiA 301 §7.2.4.3, ETG.1000.6 §5.6.2;
// shared/spec/coe-mailbox.md §5.1). Bits 7:5 are the command specifier.
#pragma once

#include <cstdint>

namespace ecat::coe::sdo {

inline constexpr unsigned kSpecifierShift = 5;
// Client (master) command specifiers.
inline constexpr std::uint8_t kCcsDownloadSegment = 0;
inline constexpr std::uint8_t kCcsInitiateDownload = 1;
inline constexpr std::uint8_t kCcsInitiateUpload = 2;
inline constexpr std::uint8_t kCcsUploadSegment = 3;
inline constexpr std::uint8_t kCsAbort = 4;
// Server (slave) command specifiers.
inline constexpr std::uint8_t kScsUploadSegment = 0;
inline constexpr std::uint8_t kScsDownloadSegment = 1;
inline constexpr std::uint8_t kScsInitiateUpload = 2;
inline constexpr std::uint8_t kScsInitiateDownload = 3;

// Initiate frames.
inline constexpr std::uint8_t kSizeIndicated = 0x01;
inline constexpr std::uint8_t kExpedited = 0x02;
inline constexpr unsigned kUnusedShift = 2;  // bits 3:2, bytes of data[4] not used
inline constexpr std::uint8_t kUnusedMask = 0x03;
inline constexpr std::uint8_t kCompleteAccess = 0x10;
// Segment frames.
inline constexpr std::uint8_t kLastSegment = 0x01;
inline constexpr unsigned kSegUnusedShift = 1;  // bits 3:1
inline constexpr std::uint8_t kSegUnusedMask = 0x07;
inline constexpr std::uint8_t kToggle = 0x10;

inline constexpr std::size_t kHeaderSize = 8;         // command, index, subindex, 4 data bytes
inline constexpr std::size_t kExpeditedMax = 4;
inline constexpr std::size_t kSegmentHeaderSize = 1;  // command only
inline constexpr std::size_t kMinSegmentData = 7;     // shorter segments are padded to 7

constexpr std::uint8_t command(std::uint8_t specifier, std::uint8_t flags = 0) noexcept {
  return static_cast<std::uint8_t>((specifier << kSpecifierShift) | flags);
}

}  // namespace ecat::coe::sdo
