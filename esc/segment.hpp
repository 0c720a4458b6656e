// A line of ESCs in one process, wired as real slaves are: each slave's
// port 1 to the next slave's port 0, the master on the first slave's port 0,
// unconnected ports closed (looped back) as an ET1100 in Auto loop mode
// (Section I §3.5). process_frame() carries an Ethernet frame through the
// line in place, as the wire would (ETG.1000.4 §5; shared/spec/esc-registers.md §1.4).
//
// Speed: the frame is parsed once (fixed-capacity datagram table, no heap);
// every slave then walks the table, so a slave's cost follows the datagrams
// and the bytes it maps, not the frame length. The time is read once.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "common/clock.hpp"
#include "common/frame_parser.hpp"
#include "esc/esc.hpp"

namespace ecat::esc {

inline constexpr unsigned kUpstreamPort = 0;
inline constexpr unsigned kDownstreamPort = 1;

class Segment {
 public:
  // Wire-plus-processing delay from one slave's port 0 to the next's,
  // used for the port arrival times handed to each DC unit.
  static constexpr Nanoseconds kDefaultHopDelay{1000};

  Segment() = default;
  explicit Segment(Nanoseconds hop_delay) : hop_delay_(hop_delay) {}

  // Appends `esc` at the end of the line (set-up only; the Esc must outlive
  // the Segment). Updates the port links of it and its predecessor.
  void add(Esc& esc);
  std::size_t size() const noexcept { return escs_.size(); }
  Esc& operator[](std::size_t i) noexcept { return *escs_[i]; }

  // Carries `frame` (a whole Ethernet frame) through the line at time `now`:
  // every reached ESC processes it in order, then the source MAC gets the
  // "processed" bit. Returns false, and leaves every ESC unchanged except
  // its error counters, if the frame is malformed; false also when the
  // frame is lost (destroyed as circulating, or sent out of an open port
  // with no link). Non-EtherCAT frames return false and count nothing.
  bool process_frame(std::span<std::uint8_t> frame, Nanoseconds now) noexcept;

  // Runs every ESC's timers; returns the earliest next deadline.
  std::optional<Nanoseconds> poll(Nanoseconds now) noexcept;

  std::uint64_t frames_processed() const noexcept { return processed_; }
  std::uint64_t frames_dropped() const noexcept { return dropped_; }
  FrameError last_error() const noexcept { return last_error_; }

 private:
  std::vector<Esc*> escs_;
  Nanoseconds hop_delay_ = kDefaultHopDelay;
  std::uint64_t processed_ = 0;
  std::uint64_t dropped_ = 0;
  FrameError last_error_ = FrameError::TooShort;
};

}  // namespace ecat::esc
