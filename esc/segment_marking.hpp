// Segment::mark_addressed: the one planning walk of a frame that skips, for
// the line (Segment::plan) and for trees and rings (Segment::plan_route).
// Only the two .cpp files of Segment include it.
#pragma once

#include "esc/datagram_engine.hpp"
#include "esc/segment.hpp"

namespace ecat::esc {

// A 16-bit ADP counts 65536 positions and wraps (Section I Table 5).
inline constexpr std::size_t kAdpPositions = std::size_t{1} << 16;

template <class EscAt>
inline void Segment::mark_addressed(DatagramView first, std::size_t count, std::size_t positions, EscAt esc_at) noexcept {
  index_.begin_frame();
  auto_increments_ = 0;
  DatagramView dg = first;
  for (std::size_t left = count;;) {
    const engine_detail::CommandTraits& traits = engine_detail::kCommandTraits[static_cast<std::uint8_t>(dg.command())];
    switch (traits.mode) {
      case Addressing::None:
      case Addressing::Broadcast:  // not planned: enters_all
        break;
      case Addressing::AutoIncrement: {
        const std::uint16_t adp = dg.adp();
        auto_increment_[auto_increments_++] = AutoIncrement{dg, adp};
        // Addressed where the ADP has been incremented to 0 (Section I Table 5).
        // Past 65536 positions the 16-bit ADP wraps and reaches 0 again.
        for (std::size_t at = static_cast<std::uint16_t>(-adp); at < positions; at += kAdpPositions) {
          index_.mark(esc_at(at));
        }
        break;
      }
      case Addressing::Configured:
        index_.mark_address(dg.adp());
        break;
      case Addressing::Logical:
        index_.mark_logical(dg.logical_address(), dg.length());
        break;
    }
    if (--left == 0) break;
    dg = dg.next();
  }
}

}  // namespace ecat::esc
