// Just enough master to drive one emulated ESC over esc::Segment: single
// datagram frames, station address 0x1001, mailbox write/read as SOEM does
// (whole SM areas, status poll at 0x080D, repeat toggle at 0x080E).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "common/clock.hpp"
#include "common/command.hpp"
#include "common/frame_builder.hpp"
#include "esc/segment.hpp"

namespace ecat::coe::test {

struct MiniMaster {
  static constexpr std::uint16_t kStation = 0x1001;

  struct Result {
    std::vector<std::uint8_t> data;
    std::uint16_t wkc = 0;
  };

  MiniMaster(esc::Segment& segment, ManualClock& clock) : segment_(segment), clock_(clock) {}

  Result exchange(Command cmd, std::uint16_t adp, std::uint16_t ado, ConstBytes data) {
    std::array<std::uint8_t, 1600> buf{};
    FrameBuilder b(buf);
    auto at = b.append(cmd, index_++, static_cast<std::uint32_t>(adp) | (static_cast<std::uint32_t>(ado) << 16), data);
    Bytes frame = b.finish();
    clock_.advance(Nanoseconds{10000});
    segment_.process_frame(frame, clock_.now());
    DatagramView d = b.datagram_at(*at);
    return {std::vector<std::uint8_t>(d.data().begin(), d.data().end()), d.wkc()};
  }
  Result fprd(std::uint16_t ado, std::size_t n) {
    std::vector<std::uint8_t> zeros(n);
    return exchange(Command::Fprd, kStation, ado, zeros);
  }
  std::uint16_t fpwr(std::uint16_t ado, std::vector<std::uint8_t> data) {
    return exchange(Command::Fpwr, kStation, ado, data).wkc;
  }
  void assign_station() {
    std::uint8_t a[2] = {static_cast<std::uint8_t>(kStation), static_cast<std::uint8_t>(kStation >> 8)};
    exchange(Command::Apwr, 0, 0x0010, a);
  }

 private:
  esc::Segment& segment_;
  ManualClock& clock_;
  std::uint8_t index_ = 0;
};

}  // namespace ecat::coe::test
