// What an Esc keeps of the line segment that may let frames pass it by
// (issue 16 item 5, docs/esc.md "Skipping ESCs a frame does not address").
//
// A frame that does not address an ESC changes nothing in it but two times:
// the time of its latest access (Esc::last_time) and the latest time its DC
// unit has seen. The segment does not write them at every ESC of every
// frame; it keeps the latest frame of its line (LinePass), and each ESC
// derives its own times from it when anything next looks (Esc::sync_pass).
// Any access to an ESC from outside a frame (PDI, poll, link, reset) also
// sets its bit in the segment's "dirty" set, so the segment reads its state
// again before the next frame decides whether to pass it by.
#pragma once

#include <cstdint>

#include "common/clock.hpp"

namespace ecat::esc {

// One master port's latest frame through a tree or ring (esc::Segment's
// route path, esc/segment_route.cpp): per ESC, when its processing unit
// had the frame and the latest time the frame passed it (at any port),
// relative to `start`; kNoTime where it did not.
struct RoutePass {
  static constexpr Nanoseconds kNoTime = Nanoseconds::max();
  std::uint64_t frame = 0;  // the LinePass::frame it was given; 0: none yet
  Nanoseconds start{0};     // when the master sent it
  const Nanoseconds* unit_at = nullptr;
  const Nanoseconds* seen_at = nullptr;
};

// The latest frame carried along a line (esc::Segment's line path).
struct LinePass {
  std::uint64_t frame = 0;  // its number, from 1; 0: none yet
  Nanoseconds start{0};     // when it reached the first ESC
  // From one ESC's port 0 to the next one's: its processing delay and the
  // cable; from one ESC's port 1 to the previous one's: its forwarding
  // delay and the cable (every ESC of a line takes the same times inside).
  Nanoseconds out{0};
  Nanoseconds back{0};
  std::uint32_t reached = 0;  // ESCs whose processing unit it entered (0..reached-1)
  bool returned = false;      // it came back through them (their port-1 arrival times)
  // Trees and rings: `frame` is the latest frame of either master port, and
  // each port's latest is here ([0], [1]); null on a line.
  const RoutePass* routes = nullptr;

  // When it reached ESC `index`'s port 0, and the latest time that ESC saw
  // it: when it returned, its arrival at port 1 on the way back - the last
  // reached ESC turned it round (reached steps out), then reached - 2 -
  // index steps back; the last reached ESC saw it only at port 0.
  Nanoseconds at(std::uint32_t index) const noexcept { return start + out * static_cast<std::int64_t>(index); }
  Nanoseconds latest(std::uint32_t index) const noexcept {
    if (!returned || index + 1 >= reached) return at(index);
    return start + out * static_cast<std::int64_t>(reached) + back * static_cast<std::int64_t>(reached - 2 - index);
  }
};

// An Esc's link to the segment that may skip it (all null when it is in none).
struct PassHook {
  const LinePass* line = nullptr;
  std::uint64_t* dirty_word = nullptr;  // the word of the segment's dirty set
  std::uint64_t dirty_bit = 0;
  std::uint32_t index = 0;   // position in the line
  // Accessed from outside a frame since the segment's user last took the
  // ESC's state in (Esc::accessed): set by every such access, as the dirty
  // bit is, but cleared by that user, not the segment. (In the padding
  // after `index`: the Esc's members after the hook stay where they were.)
  bool accessed = false;
  std::uint64_t synced = 0;  // the LinePass::frame its times include
};

}  // namespace ecat::esc
