#include "slave/lane_choice.hpp"

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "slave/chain.hpp"

namespace ecat::slave {
namespace {

constexpr unsigned kLanes = 2;
// A SCHED_FIFO loop leaves a CPU to the rest of the host (a master beside it).
constexpr unsigned kCpusForRealtimeLanes = 3;

// cache_line_round_trip: the clock is read every kTripsPerLook trips, and
// every kSpinsPerLook spins inside a trip.
constexpr unsigned kTripsPerLook = 16;
constexpr unsigned kSpinsPerLook = 1024;

unsigned cpus_needed(const LaneHost& host) noexcept { return host.realtime ? kCpusForRealtimeLanes : kLanes; }

}  // namespace

bool round_trip_decides(const LaneHost& host) noexcept {
  return host.cpus >= cpus_needed(host) && host.slaves >= Chain::kMinSplitSlaves && host.slaves_run_apart;
}

LaneChoice choose_firmware_threads(const LaneHost& host) {
  if (host.cpus < cpus_needed(host)) {
    return {1, host.realtime ? fmt::format("{} CPU(s) with --rt-priority: a spinning FIFO helper would take the CPU "
                                           "the rest of the host needs ({} needed)",
                                           host.cpus, kCpusForRealtimeLanes)
                             : fmt::format("{} CPU(s): the helper would take the loop's own", host.cpus)};
  }
  if (host.slaves < Chain::kMinSplitSlaves) {
    return {1, fmt::format("{} slave(s): fewer than the {} a run needs to be split", host.slaves,
                           Chain::kMinSplitSlaves)};
  }
  if (!host.slaves_run_apart) {
    return {1, "a slave's firmware writes outside itself (a trace, an SPI PDI or an external firmware)"};
  }
  if (!host.round_trip) return {1, "the cores' round trip was not measured"};
  const auto ns = host.round_trip->count();
  if (*host.round_trip > kMaxLaneRoundTrip) {
    return {1, fmt::format("a cache line between the cores and back takes {} ns, more than {} ns: two threads "
                           "would be slower than one",
                           ns, kMaxLaneRoundTrip.count())};
  }
  return {kLanes, fmt::format("{} slaves, {} CPUs, a cache line between the cores and back in {} ns", host.slaves,
                              host.cpus, ns)};
}

Nanoseconds cache_line_round_trip(unsigned trips, unsigned rounds, Nanoseconds max_round) {
  trips = std::max(trips, 1u);
  rounds = std::max(rounds, 1u);
  // Shared with the other thread, which is left behind (detached) when it
  // never ran: joining it would wait for the scheduler as long as the trip.
  // Whichever of the two lets go of it last deletes it.
  struct Court {
    alignas(64) std::atomic<std::uint64_t> ball{0};
    std::atomic<bool> done{false};
    std::atomic<unsigned> holders{2};
    static void let_go(Court* c) noexcept {
      if (c->holders.fetch_sub(1, std::memory_order_acq_rel) == 1) delete c;
    }
  };
  std::vector<Nanoseconds> per_trip;
  per_trip.reserve(rounds);
  Court* const court = new Court;
  // The other thread answers every odd value with the next even one.
  std::thread other;
  try {
    other = std::thread([court] {
      std::uint64_t answered = 0;
      while (!court->done.load(std::memory_order_relaxed)) {
        const std::uint64_t v = court->ball.load(std::memory_order_acquire);
        if (v != answered && (v & 1) != 0) {
          court->ball.store(v + 1, std::memory_order_release);
          answered = v + 1;
        }
      }
      Court::let_go(court);
    });
  } catch (...) {
    delete court;
    throw;
  }
  std::uint64_t v = 0;
  // Serves the ball (the next odd value) and waits for its answer, at most
  // until `start` + max_round: false when none came (a host too busy to run
  // the other thread then reads as a far core, never a hang).
  const auto trip = [&](std::chrono::steady_clock::time_point start) noexcept {
    court->ball.store(++v, std::memory_order_release);
    for (unsigned spins = 1; court->ball.load(std::memory_order_acquire) != v + 1; ++spins) {
      if (spins % kSpinsPerLook == 0 && std::chrono::steady_clock::now() - start > max_round) return false;
    }
    ++v;
    return true;
  };
  // The first trip only says that the other thread runs: its start-up (a
  // halted vCPU to wake, a CPU to be given) is no trip.
  const auto handshake = std::chrono::steady_clock::now();
  bool answered = trip(handshake);  // false: a trip was never answered within max_round
  if (!answered) per_trip.push_back(std::chrono::steady_clock::now() - handshake);
  for (unsigned r = 0; r < rounds && answered; ++r) {
    const auto start = std::chrono::steady_clock::now();
    Nanoseconds elapsed{0};
    unsigned done_trips = 0;
    while (done_trips < trips) {
      answered = trip(start);
      if (!answered) break;
      // A busy host ends the round early: its figure is that of a slow host.
      if (++done_trips % kTripsPerLook == 0) {
        elapsed = std::chrono::steady_clock::now() - start;
        if (elapsed > max_round) break;
      }
    }
    elapsed = std::chrono::steady_clock::now() - start;
    // An unanswered trip took at least the whole round.
    per_trip.push_back(answered ? elapsed / done_trips : elapsed);
  }
  court->done.store(true);
  if (answered) {
    other.join();
  } else {
    other.detach();
  }
  Court::let_go(court);
  std::nth_element(per_trip.begin(), per_trip.begin() + per_trip.size() / 2, per_trip.end());
  return per_trip[per_trip.size() / 2];
}

}  // namespace ecat::slave
