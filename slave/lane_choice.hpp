// How many threads a chain's firmware should run on, chosen from the host
// (ecat-slave --firmware-threads auto; issue 30 item 3). Two threads give
// 0.70-0.80x the wall time of a 1000-drive cycle when the host's cores pass
// a cache line between them quickly, and 1.4-2.4x when they do not (the
// VM's vCPUs placed far apart: 390-480 ns there and back); the helper spins
// between frames, so it takes a CPU of its own (docs/performance-log.md
// "Firmware lanes" and "Session 19: --firmware-threads auto").
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "common/clock.hpp"

namespace ecat::slave {

// A cache line to the other core and back above this, two threads are not
// chosen: measured gains at 83-229 ns, losses at 383-480 ns.
inline constexpr Nanoseconds kMaxLaneRoundTrip{250};

struct LaneHost {
  unsigned cpus = 1;              // CPUs this process may run on (sched_getaffinity)
  bool realtime = false;          // the loop runs at a SCHED_FIFO priority (--rt-priority)
  std::size_t slaves = 0;         // in the chain
  bool slaves_run_apart = true;   // Chain::slaves_run_apart: no trace, SPI PDI, external firmware
  std::optional<Nanoseconds> round_trip;  // cache_line_round_trip(), when measured
};

struct LaneChoice {
  unsigned threads = 1;
  std::string reason;  // why, in words for the user
};

// Whether only the round trip is left to decide: every other condition
// allows two threads, so it is worth measuring (a few milliseconds).
bool round_trip_decides(const LaneHost& host) noexcept;

// Two threads when the chain has enough slaves to split (Chain::
// kMinSplitSlaves) whose firmware may run apart, the process may use two
// CPUs (three with a SCHED_FIFO loop: a spinning FIFO helper would take the
// CPU a master on a two-CPU host needs), and the measured round trip is at
// most kMaxLaneRoundTrip; else one. Without a measured round trip, one.
LaneChoice choose_firmware_threads(const LaneHost& host);

// The median time of a cache line from this thread to a second one and
// back (an atomic this thread writes and the other answers), over `rounds`
// rounds of `trips` round trips on the real clock: what the lanes'
// hand-off and the ESC lines a helper wrote cost each time. A round ends
// after `max_round` whatever it did (a host too busy to run the second
// thread then reads as a far core).
inline constexpr Nanoseconds kMaxRoundTripRound = std::chrono::milliseconds(20);
Nanoseconds cache_line_round_trip(unsigned trips = 2000, unsigned rounds = 5,
                                  Nanoseconds max_round = kMaxRoundTripRound);

}  // namespace ecat::slave
