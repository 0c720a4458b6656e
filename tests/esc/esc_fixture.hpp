// Shared helpers for the ESC tests: a valid SII image, and a tiny master
// that sends one frame of datagrams through a Segment and reads the result.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <vector>

#include "common/frame_builder.hpp"
#include "common/frame_parser.hpp"
#include "esc/esc.hpp"
#include "esc/registers.hpp"
#include "esc/segment.hpp"
#include "esc/sii_interface.hpp"

namespace ecat::esc::test {

using namespace std::chrono_literals;
using Data = std::vector<std::uint8_t>;

// 256-byte SII: PDI control 0x05 (SPI), ESC config 0x0C, PDI config 0x44 / 0x33,
// sync pulse 0x0064, extended PDI 0x1234, alias 0x0ABC, CRC in word 7,
// then words 8.. = 0x0100 + word number (easy to recognise).
inline Data make_sii(std::uint16_t alias = 0x0ABC) {
  Data s(256, 0);
  auto put = [&](std::size_t w, std::uint16_t v) {
    s[2 * w] = static_cast<std::uint8_t>(v);
    s[2 * w + 1] = static_cast<std::uint8_t>(v >> 8);
  };
  put(0, 0x0C05);
  put(1, 0x3344);
  put(2, 0x0064);
  put(3, 0x1234);
  put(4, alias);
  put(7, sii_crc(std::span(s.data(), kSiiConfigAreaBytes)));
  for (std::size_t w = 8; w < s.size() / 2; ++w) put(w, static_cast<std::uint16_t>(0x0100 + w));
  return s;
}

inline EscConfig make_config() {
  EscConfig c;
  c.sii = make_sii();
  return c;
}

// N ESCs in a line, sharing one manual clock.
struct Line {
  explicit Line(std::size_t n, EscConfig cfg = make_config()) {
    for (std::size_t i = 0; i < n; ++i) {
      escs.push_back(std::make_unique<Esc>(cfg, clock));
      segment.add(*escs.back());
    }
  }
  Esc& operator[](std::size_t i) { return *escs[i]; }
  ManualClock clock;
  std::vector<std::unique_ptr<Esc>> escs;
  Segment segment;
};

// One frame under construction / after the trip through a segment.
class TestFrame {
 public:
  TestFrame() : builder_(buf_, kBroadcastMac, MacAddress{0x00, 0x11, 0x22, 0x33, 0x44, 0x55}) {}
  TestFrame(const TestFrame&) = delete;
  TestFrame& operator=(const TestFrame&) = delete;

  std::size_t add(Command c, std::uint32_t address, const Data& data) {
    at_.push_back(builder_.append(c, static_cast<std::uint8_t>(at_.size()), address, data).value());
    return at_.size() - 1;
  }
  std::size_t add(Command c, std::uint32_t address, std::uint16_t length) {
    at_.push_back(builder_.append_zeros(c, static_cast<std::uint8_t>(at_.size()), address, length).value());
    return at_.size() - 1;
  }
  bool send(Segment& s, Nanoseconds now = Nanoseconds{0}) {
    frame_ = builder_.finish();
    return s.process_frame(frame_, now);
  }
  // The same on master port `master_port` (a ring's redundant port: 1).
  Delivery send_on(Segment& s, Nanoseconds now, unsigned master_port) {
    frame_ = builder_.finish();
    return s.send(frame_, now, master_port);
  }
  DatagramView dg(std::size_t i) const { return DatagramView(buf_.data() + at_[i]); }
  std::uint16_t wkc(std::size_t i) const { return dg(i).wkc(); }
  Data data(std::size_t i) const {
    auto d = dg(i).data();
    return Data(d.begin(), d.end());
  }
  Bytes frame() const { return frame_; }

 private:
  mutable std::array<std::uint8_t, 1600> buf_{};
  FrameBuilder builder_;
  std::vector<std::size_t> at_;
  Bytes frame_;
};

struct Reply {
  std::uint16_t wkc;
  Data data;
  std::uint16_t adp;
};

inline Reply transact(Segment& s, Command c, std::uint32_t address, const Data& data, Nanoseconds now = {}) {
  TestFrame f;
  f.add(c, address, data);
  EXPECT_TRUE(f.send(s, now));
  return Reply{f.wkc(0), f.data(0), f.dg(0).adp()};
}
inline Reply transact(Segment& s, Command c, std::uint32_t address, std::uint16_t length, Nanoseconds now = {}) {
  return transact(s, c, address, Data(length, 0), now);
}
inline std::uint32_t fp(std::uint16_t station, std::uint16_t ado) { return device_address(station, ado); }
inline std::uint32_t ap(std::uint16_t position, std::uint16_t ado) {
  return device_address(auto_increment_adp(position), ado);
}
inline Data le16(std::uint16_t v) { return Data{static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8)}; }
inline Data le32(std::uint32_t v) {
  return Data{static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8), static_cast<std::uint8_t>(v >> 16),
              static_cast<std::uint8_t>(v >> 24)};
}

// Gives station addresses 0x1001.. to every slave (as masters do at scan).
inline void assign_stations(Line& line) {
  for (std::size_t i = 0; i < line.escs.size(); ++i) {
    transact(line.segment, Command::Apwr, ap(static_cast<std::uint16_t>(i), reg::kConfiguredStationAddress),
             le16(static_cast<std::uint16_t>(0x1001 + i)));
  }
}

// Configures SM n via ECAT: start, length, control, activate.
inline void config_sm(Segment& s, std::uint16_t station, unsigned n, std::uint16_t start, std::uint16_t length,
                      std::uint8_t control, std::uint8_t activate = 1) {
  Data d{static_cast<std::uint8_t>(start), static_cast<std::uint8_t>(start >> 8), static_cast<std::uint8_t>(length),
         static_cast<std::uint8_t>(length >> 8), control, 0, activate, 0};
  transact(s, Command::Fpwr, fp(station, reg::sync_manager(n)), d);
}

// The 16 bytes of an enabled FMMU (Section II 0x0600 + 16 n).
inline Data fmmu_bytes(std::uint32_t logical, std::uint16_t length, std::uint8_t start_bit, std::uint8_t stop_bit,
                       std::uint16_t physical, std::uint8_t physical_bit, std::uint8_t type) {
  Data d = le32(logical);
  for (auto b : le16(length)) d.push_back(b);
  d.push_back(start_bit);
  d.push_back(stop_bit);
  for (auto b : le16(physical)) d.push_back(b);
  d.push_back(physical_bit);
  d.push_back(type);
  d.push_back(1);  // enable
  d.resize(16, 0);
  return d;
}

// Configures FMMU n via ECAT.
inline void config_fmmu(Segment& s, std::uint16_t station, unsigned n, std::uint32_t logical, std::uint16_t length,
                        std::uint8_t start_bit, std::uint8_t stop_bit, std::uint16_t physical,
                        std::uint8_t physical_bit, std::uint8_t type) {
  transact(s, Command::Fpwr, fp(station, reg::fmmu(n)),
           fmmu_bytes(logical, length, start_bit, stop_bit, physical, physical_bit, type));
}

// The first byte at which two ESCs' memories differ, or nothing. memcmp
// first: a byte loop in a test built at -O0 under ASan took most of the
// random-sequence tests' time (85 s of each, 1.3 s without sanitizers).
inline std::optional<std::size_t> first_memory_difference(const Esc& x, const Esc& y) {
  const std::size_t n = std::min(x.memory_size(), y.memory_size());
  if (x.memory_size() == y.memory_size() && std::memcmp(x.memory(), y.memory(), n) == 0) return std::nullopt;
  for (std::size_t a = 0; a < n; ++a) {
    if (x.memory()[a] != y.memory()[a]) return a;
  }
  return n;
}

}  // namespace ecat::esc::test
