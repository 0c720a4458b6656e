// A minimal master for the benchmarks: builds frames with common/frame_builder
// and sends them through an esc::Segment, so the ESCs are configured exactly
// as a master configures them on the wire (station addresses by APWR, sync
// managers and FMMUs by FPWR). Set-up only: it allocates freely.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/frame_builder.hpp"
#include "common/frame_parser.hpp"
#include "esc/esc.hpp"
#include "esc/fmmu.hpp"
#include "esc/registers.hpp"
#include "esc/segment.hpp"
#include "esc/sii_interface.hpp"

namespace ecat::bench {

using Data = std::vector<std::uint8_t>;

// First configured station address a master hands out (as SOEM/TwinCAT do).
inline constexpr std::uint16_t kFirstStation = 0x1001;
// Largest frame buffer the benchmarks build (Ethernet maximum without FCS).
inline constexpr std::size_t kFrameBufferSize = kEthernetHeaderSize + kMaxEthernetPayload;
// A datagram filling a whole frame: 1500 - 2 - 12 = 1486 data bytes.
inline constexpr std::uint16_t kFullFrameData = static_cast<std::uint16_t>(kMaxDatagramData);

// SM control bytes of a CiA 402 device (ETG.1000.4 §6.7.2): 3-buffer,
// ECAT writes (outputs, with watchdog trigger) / ECAT reads (inputs).
inline constexpr std::uint8_t kSmControlOutputs = 0x64;
inline constexpr std::uint8_t kSmControlInputs = 0x20;
inline constexpr std::uint8_t kSmActivate = 0x01;

inline constexpr std::uint16_t kSmOutputsStart = 0x1100;
inline constexpr std::uint16_t kSmInputsStart = 0x1A00;

// A 256-byte SII whose configuration area has a valid CRC (ETG.2010 §2).
inline Data make_sii() {
  Data s(256, 0);
  s[esc::kSiiConfigAreaBytes] = esc::sii_crc(std::span(s.data(), esc::kSiiConfigAreaBytes));
  return s;
}

inline esc::EscConfig make_esc_config() {
  esc::EscConfig c;
  c.sii = make_sii();
  return c;
}

// One frame with datagrams appended by the caller, kept for repeated sends.
class Frame {
 public:
  Frame() : builder_(buf_, kBroadcastMac, MacAddress{0x02, 0x00, 0x00, 0x00, 0x00, 0x01}) {}
  Frame(const Frame&) = delete;
  Frame& operator=(const Frame&) = delete;

  std::size_t add(Command c, std::uint32_t address, const Data& data) {
    at_.push_back(check(builder_.append(c, static_cast<std::uint8_t>(at_.size()), address, data)));
    return at_.size() - 1;
  }
  std::size_t add(Command c, std::uint32_t address, std::uint16_t length) {
    at_.push_back(check(builder_.append_zeros(c, static_cast<std::uint8_t>(at_.size()), address, length)));
    return at_.size() - 1;
  }
  std::span<std::uint8_t> finish() { return frame_ = builder_.finish(); }
  std::span<std::uint8_t> bytes() const { return frame_; }
  DatagramView dg(std::size_t i) const { return DatagramView(buf_.data() + at_[i]); }
  std::uint16_t wkc(std::size_t i) const { return dg(i).wkc(); }
  std::size_t remaining() const { return builder_.remaining_data_capacity(); }

 private:
  static std::size_t check(const Expected<std::size_t, FrameError>& r) {
    if (!r) throw std::runtime_error(std::string("frame: ") + to_string(r.error()));
    return *r;
  }
  mutable std::array<std::uint8_t, kFrameBufferSize> buf_{};
  FrameBuilder builder_;
  std::vector<std::size_t> at_;
  std::span<std::uint8_t> frame_;
};

// Sends one datagram and returns its WKC (set-up helper).
inline std::uint16_t transact(esc::Segment& s, Command c, std::uint32_t address, const Data& data) {
  Frame f;
  f.add(c, address, data);
  if (!s.process_frame(f.finish(), Nanoseconds{0})) throw std::runtime_error("set-up frame lost");
  return f.wkc(0);
}

inline Data le16(std::uint16_t v) { return Data{static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8)}; }
inline Data le32(std::uint32_t v) {
  return Data{static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8), static_cast<std::uint8_t>(v >> 16),
              static_cast<std::uint8_t>(v >> 24)};
}
inline std::uint16_t station(std::size_t position) { return static_cast<std::uint16_t>(kFirstStation + position); }

// Station addresses kFirstStation.. by auto-increment writes, as at a scan.
inline void assign_stations(esc::Segment& s) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    transact(s, Command::Apwr,
             device_address(auto_increment_adp(static_cast<std::uint16_t>(i)), esc::reg::kConfiguredStationAddress),
             le16(station(i)));
  }
}

inline void config_sm(esc::Segment& s, std::uint16_t st, unsigned n, std::uint16_t start, std::uint16_t length,
                      std::uint8_t control) {
  Data d{static_cast<std::uint8_t>(start), static_cast<std::uint8_t>(start >> 8), static_cast<std::uint8_t>(length),
         static_cast<std::uint8_t>(length >> 8), control, 0, kSmActivate, 0};
  transact(s, Command::Fpwr, device_address(st, esc::reg::sync_manager(n)), d);
}

// Byte-aligned FMMU `n`: `length` bytes at `logical` onto `physical`.
inline void config_fmmu(esc::Segment& s, std::uint16_t st, unsigned n, std::uint32_t logical, std::uint16_t length,
                        std::uint16_t physical, std::uint8_t type) {
  constexpr std::uint8_t kLastBit = 7;
  Data d = le32(logical);
  for (auto b : le16(length)) d.push_back(b);
  d.push_back(0);
  d.push_back(kLastBit);
  for (auto b : le16(physical)) d.push_back(b);
  d.push_back(0);
  d.push_back(type);
  d.push_back(esc::fmmu_reg::kActivateEnable);
  d.resize(esc::reg::kFmmuStride, 0);
  transact(s, Command::Fpwr, device_address(st, esc::reg::fmmu(n)), d);
}

// Maps `out` output bytes at `logical` and `in` input bytes right after them
// on slave `st`: SM2/SM3 3-buffered, FMMU0 write, FMMU1 read.
inline void map_process_data(esc::Segment& s, std::uint16_t st, std::uint32_t logical, std::uint16_t out,
                             std::uint16_t in) {
  config_sm(s, st, 2, kSmOutputsStart, out, kSmControlOutputs);
  config_sm(s, st, 3, kSmInputsStart, in, kSmControlInputs);
  config_fmmu(s, st, 0, logical, out, kSmOutputsStart, esc::fmmu_reg::kTypeWrite);
  config_fmmu(s, st, 1, logical + out, in, kSmInputsStart, esc::fmmu_reg::kTypeRead);
}

// N bare ESCs in a line (no firmware), with station addresses assigned.
struct EscLine {
  explicit EscLine(std::size_t n, const esc::EscConfig& cfg = make_esc_config()) {
    escs.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
      esc::EscConfig c = cfg;
      c.memory_colour = esc::EscConfig::memory_colour_at(i);  // as slave::Chain colours its slaves
      escs.push_back(std::make_unique<esc::Esc>(c, clock));
      segment.add(*escs.back());
    }
    assign_stations(segment);
  }
  ManualClock clock;
  std::vector<std::unique_ptr<esc::Esc>> escs;
  esc::Segment segment;
};

}  // namespace ecat::bench
