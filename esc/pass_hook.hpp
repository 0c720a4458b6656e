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

// The latest frame carried along a line (esc::Segment's line path).
struct LinePass {
  std::uint64_t frame = 0;  // its number, from 1; 0: none yet
  Nanoseconds start{0};     // when it reached the first ESC
  Nanoseconds hop{0};       // cable delay between neighbours
  std::uint32_t reached = 0;  // ESCs whose processing unit it entered (0..reached-1)
  bool returned = false;      // it came back through them (their port-1 arrival times)

  // When it reached ESC `index`'s port 0, and the latest time that ESC saw
  // it (on its way back when it returned: 2 (reached - 1) - index hops).
  Nanoseconds at(std::uint32_t index) const noexcept { return start + hop * static_cast<std::int64_t>(index); }
  Nanoseconds latest(std::uint32_t index) const noexcept {
    if (!returned) return at(index);
    return start + hop * static_cast<std::int64_t>(2 * (reached - 1) - index);
  }
};

// An Esc's link to the segment that may skip it (all null when it is in none).
struct PassHook {
  const LinePass* line = nullptr;
  std::uint64_t* dirty_word = nullptr;  // the word of the segment's dirty set
  std::uint64_t dirty_bit = 0;
  std::uint32_t index = 0;   // position in the line
  std::uint64_t synced = 0;  // the LinePass::frame its times include
};

}  // namespace ecat::esc
