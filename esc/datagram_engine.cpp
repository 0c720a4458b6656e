// The datagram engine, out-of-line parts (the per-frame pass is inline in
// esc/datagram_engine.hpp): Esc::process for callers other than
// esc::Segment, and the commands that merge the data through a scratch
// copy (xRW, BRD).
#include "esc/datagram_engine.hpp"

#include <cstring>

namespace ecat::esc {

bool Esc::process(const FrameView& frame, Nanoseconds now) noexcept {
  touch();
  if (frame.empty()) {
    // Nothing to walk; the timers, the DC arrival and the per-frame write
    // enables behave as for any frame.
    run_timers(now);
    now_ = now;
    dc_.on_frame_arrival(0, now);
    register_write_enabled_ = false;
    esc_write_enabled_ = false;
    return true;
  }
  if (process_datagrams(frame.front(), frame.size(), now)) return true;
  count_processing_unit_error();  // a circulating frame destroyed (Section I §14.1 Table 51)
  return false;
}

// xRW: read first (the data returned is the memory before the write), then
// write the incoming data; BRW ORs the read into the data. BRD: the data of
// all slaves ORed together.
void Esc::process_merged(DatagramView d, bool read_write, bool broadcast) noexcept {
  const std::uint16_t ado = d.ado();
  Bytes data = d.data();
  std::uint16_t wkc = 0;
  if (read_write) {
    DatagramScratch incoming;
    std::memcpy(incoming.data(), data.data(), data.size());
    DatagramScratch result;
    std::memset(result.data(), 0, data.size());
    if (mem_read(ado, std::span(result.data(), data.size()), Side::Ecat)) {
      wkc = static_cast<std::uint16_t>(wkc + kWkcRead);
      for (std::size_t i = 0; i < data.size(); ++i) {
        data[i] = broadcast ? static_cast<std::uint8_t>(data[i] | result[i]) : result[i];
      }
    }
    if (mem_write(ado, std::span<const std::uint8_t>(incoming.data(), data.size()), Side::Ecat)) {
      wkc = static_cast<std::uint16_t>(wkc + kWkcReadWriteWrite);
    }
  } else {
    DatagramScratch result;
    std::memset(result.data(), 0, data.size());
    if (mem_read(ado, std::span(result.data(), data.size()), Side::Ecat)) {
      wkc = kWkcRead;
      for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<std::uint8_t>(data[i] | result[i]);
    }
  }
  d.add_wkc(wkc);
}

}  // namespace ecat::esc
