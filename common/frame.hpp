// EtherCAT wire format as value types (ETG.1000.4 §5.3/§5.4; Beckhoff ESC
// datasheet Section I §2.5; shared/spec/esc-registers.md §1): Ethernet header
// with optional VLAN tag, the 2-byte EtherCAT frame header and the 10-byte
// datagram header. Each type unpacks from / packs into a byte span through
// common/le.hpp. Walking a whole frame: common/frame_parser.hpp; building
// one: common/frame_builder.hpp.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "common/command.hpp"
#include "common/expected.hpp"
#include "common/le.hpp"

namespace ecat {

// --- Sizes and field constants -------------------------------------------------
inline constexpr std::uint16_t kEtherTypeEtherCat = 0x88A4;
inline constexpr std::uint16_t kEtherTypeVlan = 0x8100;
inline constexpr std::size_t kMacSize = 6;
inline constexpr std::size_t kEthernetHeaderSize = 14;
inline constexpr std::size_t kVlanTagSize = 4;
inline constexpr std::size_t kMinEthernetFrame = 60;  // without FCS; shorter frames are padded
inline constexpr std::size_t kMaxEthernetPayload = 1500;
inline constexpr std::size_t kFrameHeaderSize = 2;
inline constexpr std::size_t kDatagramHeaderSize = 10;
inline constexpr std::size_t kWkcSize = 2;
inline constexpr std::size_t kDatagramOverhead = kDatagramHeaderSize + kWkcSize;
// 1500 - 2 (frame header) - 10 (datagram header) - 2 (WKC).
inline constexpr std::size_t kMaxDatagramData = kMaxEthernetPayload - kFrameHeaderSize - kDatagramOverhead;

inline constexpr std::uint16_t kFrameLengthMask = 0x07FF;  // bits 10:0
inline constexpr std::uint16_t kFrameReservedBit = 0x0800;  // bit 11
inline constexpr unsigned kFrameTypeShift = 12;             // bits 15:12
inline constexpr std::uint8_t kFrameTypeDlpdu = 1;          // EtherCAT commands
inline constexpr std::uint8_t kFrameTypeNetworkVariables = 4;
inline constexpr std::uint8_t kFrameTypeMailbox = 5;

inline constexpr std::uint16_t kDatagramLengthMask = 0x07FF;  // bits 10:0
inline constexpr std::uint16_t kDatagramReservedMask = 0x3800;  // bits 13:11
inline constexpr std::uint16_t kDatagramCirculating = 0x4000;  // bit 14 (C)
inline constexpr std::uint16_t kDatagramMore = 0x8000;         // bit 15 (M)

// The largest datagram count an 11-bit frame length can describe.
inline constexpr std::size_t kMaxDatagramsPerFrame = kFrameLengthMask / kDatagramOverhead;

// First source-MAC byte bit an ESC sets on every frame it processes
// (Section I §3.2: "SOURCE_MAC[1]" = locally administered bit).
inline constexpr std::uint8_t kSourceMacProcessedBit = 0x02;

using MacAddress = std::array<std::uint8_t, kMacSize>;
inline constexpr MacAddress kBroadcastMac{0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF};

// Why a frame was rejected (or could not be built).
enum class FrameError : std::uint8_t {
  TooShort = 1,           // fewer bytes than the headers need
  NotEtherCat,            // EtherType is not 0x88A4
  UnsupportedType,        // EtherCAT frame type other than 1 (DLPDU)
  LengthBeyondFrame,      // frame header length runs past the buffer
  DatagramBeyondFrame,    // a datagram (header, data, WKC) runs past the frame length
  LengthMismatch,         // datagrams end before the frame header length
  UnknownCommand,         // command code > 14
  TooManyDatagrams,       // more than kMaxDatagramsPerFrame
  BufferFull,             // builder: datagram does not fit the buffer / 11-bit length
};

constexpr const char* to_string(FrameError e) noexcept {
  switch (e) {
    case FrameError::TooShort: return "frame too short";
    case FrameError::NotEtherCat: return "not an EtherCAT frame";
    case FrameError::UnsupportedType: return "unsupported EtherCAT frame type";
    case FrameError::LengthBeyondFrame: return "EtherCAT length beyond frame";
    case FrameError::DatagramBeyondFrame: return "datagram beyond frame";
    case FrameError::LengthMismatch: return "datagrams do not fill the EtherCAT length";
    case FrameError::UnknownCommand: return "unknown datagram command";
    case FrameError::TooManyDatagrams: return "too many datagrams";
    case FrameError::BufferFull: return "frame buffer full";
  }
  return "?";
}

// --- Ethernet header ----------------------------------------------------------
struct EthernetHeader {
  MacAddress destination{};
  MacAddress source{};
  std::optional<std::uint16_t> vlan_tci;  // present when an 802.1Q tag precedes the EtherType
  std::uint16_t ether_type = kEtherTypeEtherCat;

  constexpr std::size_t size() const noexcept {
    return kEthernetHeaderSize + (vlan_tci ? kVlanTagSize : 0);
  }

  // The EtherType and VLAN TCI are big-endian on the wire (IEEE 802.3).
  static Expected<EthernetHeader, FrameError> unpack(ConstBytes in) noexcept {
    if (in.size() < kEthernetHeaderSize) return fail(FrameError::TooShort);
    EthernetHeader h;
    for (std::size_t i = 0; i < kMacSize; ++i) {
      h.destination[i] = in[i];
      h.source[i] = in[kMacSize + i];
    }
    std::size_t pos = 2 * kMacSize;
    std::uint16_t type = be16(in, pos);
    if (type == kEtherTypeVlan) {
      if (in.size() < kEthernetHeaderSize + kVlanTagSize) return fail(FrameError::TooShort);
      h.vlan_tci = be16(in, pos + 2);
      type = be16(in, pos + kVlanTagSize);
    }
    h.ether_type = type;
    return h;
  }

  // Writes size() bytes; returns false if `out` is too small.
  bool pack(Bytes out) const noexcept {
    if (out.size() < size()) return false;
    for (std::size_t i = 0; i < kMacSize; ++i) {
      out[i] = destination[i];
      out[kMacSize + i] = source[i];
    }
    std::size_t pos = 2 * kMacSize;
    if (vlan_tci) {
      put_be16(out, pos, kEtherTypeVlan);
      put_be16(out, pos + 2, *vlan_tci);
      pos += kVlanTagSize;
    }
    put_be16(out, pos, ether_type);
    return true;
  }

  friend bool operator==(const EthernetHeader&, const EthernetHeader&) = default;

 private:
  static constexpr std::uint16_t be16(ConstBytes in, std::size_t pos) noexcept {
    return static_cast<std::uint16_t>((in[pos] << 8) | in[pos + 1]);
  }
  static constexpr void put_be16(Bytes out, std::size_t pos, std::uint16_t v) noexcept {
    out[pos] = static_cast<std::uint8_t>(v >> 8);
    out[pos + 1] = static_cast<std::uint8_t>(v);
  }
};

// --- EtherCAT frame header (ETG.1000.4 §5.3.2) ----------------------------------
struct FrameHeader {
  std::uint16_t length = 0;  // bytes of datagrams that follow (11 bits)
  std::uint8_t type = kFrameTypeDlpdu;

  static constexpr FrameHeader decode(std::uint16_t word) noexcept {
    return FrameHeader{static_cast<std::uint16_t>(word & kFrameLengthMask),
                       static_cast<std::uint8_t>(word >> kFrameTypeShift)};
  }
  constexpr std::uint16_t encode() const noexcept {
    return static_cast<std::uint16_t>((length & kFrameLengthMask) | (type << kFrameTypeShift));
  }
  static Expected<FrameHeader, FrameError> unpack(ConstBytes in) noexcept {
    if (in.size() < kFrameHeaderSize) return fail(FrameError::TooShort);
    return decode(load_le<std::uint16_t>(in.data()));
  }
  bool pack(Bytes out) const noexcept {
    if (out.size() < kFrameHeaderSize) return false;
    store_le(out.data(), encode());
    return true;
  }
  friend bool operator==(const FrameHeader&, const FrameHeader&) = default;
};

// --- Datagram address helpers -----------------------------------------------------
// Device addressing: ADP in the low word, ADO in the high word of the 32-bit
// address field; logical addressing uses all 32 bits.
constexpr std::uint32_t device_address(std::uint16_t adp, std::uint16_t ado) noexcept {
  return static_cast<std::uint32_t>(adp) | (static_cast<std::uint32_t>(ado) << 16);
}
// ADP a master sends to reach the slave at 0-based `position` (two's complement of -position).
constexpr std::uint16_t auto_increment_adp(std::uint16_t position) noexcept {
  return static_cast<std::uint16_t>(0x10000u - position);
}

// --- Datagram header (ETG.1000.4 §5.4.1) -------------------------------------------
struct DatagramHeader {
  Command command = Command::Nop;
  std::uint8_t index = 0;
  std::uint32_t address = 0;
  std::uint16_t length = 0;  // data bytes (11 bits)
  bool circulating = false;
  bool more = false;
  std::uint16_t irq = 0;

  constexpr std::uint16_t adp() const noexcept { return static_cast<std::uint16_t>(address); }
  constexpr std::uint16_t ado() const noexcept { return static_cast<std::uint16_t>(address >> 16); }
  constexpr std::size_t wire_size() const noexcept { return kDatagramOverhead + length; }

  constexpr std::uint16_t length_word() const noexcept {
    return static_cast<std::uint16_t>((length & kDatagramLengthMask) | (circulating ? kDatagramCirculating : 0) |
                                      (more ? kDatagramMore : 0));
  }

  // Header only (10 bytes). Unknown command codes are rejected.
  static Expected<DatagramHeader, FrameError> unpack(ConstBytes in) noexcept {
    ByteReader r(in);
    std::uint8_t cmd = r.u8();
    DatagramHeader h;
    h.index = r.u8();
    h.address = r.u32();
    std::uint16_t len = r.u16();
    h.irq = r.u16();
    if (!r.ok()) return fail(FrameError::TooShort);
    if (!is_known_command(cmd)) return fail(FrameError::UnknownCommand);
    h.command = static_cast<Command>(cmd);
    h.length = static_cast<std::uint16_t>(len & kDatagramLengthMask);
    h.circulating = (len & kDatagramCirculating) != 0;
    h.more = (len & kDatagramMore) != 0;
    return h;
  }
  bool pack(Bytes out) const noexcept {
    ByteWriter w(out);
    w.u8(static_cast<std::uint8_t>(command));
    w.u8(index);
    w.u32(address);
    w.u16(length_word());
    w.u16(irq);
    return w.ok();
  }
  friend bool operator==(const DatagramHeader&, const DatagramHeader&) = default;
};

}  // namespace ecat
