// How long ecat-slave's live loop keeps polling its socket after a frame
// before it may sleep (`--spin-us auto`, the default; docs/e2e.md "Frames in
// bursts").
//
// A master's cycle is often a burst: it sends a frame, waits for it to come
// back, and sends the next (the project's master with 1000 drives sends ~27
// frames a cycle, each 10-40 us after the previous answer). A loop that goes
// to sleep after every answer pays a wake-up on each of them; on a VM whose
// idle vCPU halts, that wake-up took long enough that 750 and 1000 drives on
// one thread never reached Op (AL status code 0x001B, the SM watchdog;
// docs/performance-log.md "Session 21: --spin-us"). Spinning a fixed time after
// every frame fixes that, and costs a master that sends one frame a cycle
// the whole spin each cycle for nothing.
//
// So the spin is learned from the frames themselves. The gap of a frame is
// the time from the end of the loop's work on the previous frame (when it
// would have gone to sleep) to this frame's arrival (the kernel's stamp
// where the medium gives one). A gap of at most kBurstGap is a frame of the
// same burst; a longer one starts a new burst (the next cycle, or a master
// that sends one frame a cycle). The loop spins after a frame only while at
// least half of the last kHistory frames came in bursts, and then for twice
// the gap that three in four of their burst gaps stay within, at most
// kBurstGap; otherwise it sleeps at once, as before.
//
// Spinning is not free even for the loop's own frames: on a 2-vCPU host the
// master's wake-up for the reply can land on the spinning vCPU and wait for
// the spin to end. A master sending one frame a millisecond that now and
// then caught up with a second frame right after the first made the first
// form of this rule (every burst gap counted, spins up to 200 us) spin after
// every frame: the round trip's p99 went from 31-46 us to 120-232 us. Hence
// the half of the frames, the three in four (a late frame now and then does
// not raise the spin), and the 100 us bound.
//
// Pure and time-injected: the loop gives the times, the tests give theirs.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "common/clock.hpp"

namespace ecat::slave {

class BurstSpin {
 public:
  // A gap longer than this is between bursts: a wake-up costs less than
  // spinning through it. Also the longest spin, so at a 1 ms period the spin
  // takes at most a tenth of a core.
  static constexpr Nanoseconds kBurstGap{100'000};
  // The frames whose gaps decide the spin: a few cycles of a master with
  // tens of frames a cycle, so one late frame of the master's does not
  // raise the spin for long.
  static constexpr std::size_t kHistory = 64;
  // Spin for kSpinPerGap times the gap that kQuantileOf in kQuantileIn
  // burst gaps stay within.
  static constexpr std::size_t kQuantileOf = 3;
  static constexpr std::size_t kQuantileIn = 4;
  static constexpr std::int64_t kSpinPerGap = 2;
  // The loop spins only while at least kBurstShareOf in kBurstShareIn of the
  // remembered frames had burst gaps.
  static constexpr std::size_t kBurstShareOf = 1;
  static constexpr std::size_t kBurstShareIn = 2;

  // A frame arrived at `arrival` (the same time base as frame_done's).
  void frame_arrived(Nanoseconds arrival) noexcept;
  // The loop is done with the frame at `done`: the time it may spin from
  // now before it sleeps (0: sleep at once).
  Nanoseconds frame_done(Nanoseconds done) noexcept;
  // The spin the last frame_done gave.
  Nanoseconds spin() const noexcept { return spin_; }

 private:
  static constexpr Nanoseconds kNoGap{-1};  // between bursts, or no frame before it

  std::array<Nanoseconds, kHistory> gaps_{};   // ring of the last frames' gaps (kNoGap: none)
  std::array<Nanoseconds, kHistory> sorted_{};  // their burst gaps, ascending
  std::size_t burst_gaps_ = 0;                   // in sorted_
  std::size_t next_ = 0;
  std::size_t filled_ = 0;
  Nanoseconds last_done_{0};
  bool have_done_ = false;
  Nanoseconds spin_{0};
};

}  // namespace ecat::slave
