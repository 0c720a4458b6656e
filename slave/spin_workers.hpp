// Threads that help the loop thread with one batch of independent work at a
// time (issue 30 item 3: the firmware of a chain's slaves on two cores).
//
// run(task, context, count) calls task(context, k, lane) once for every k in
// [0, count): the calling thread (lane 0) takes them from the front, each
// helper (lanes 1..) from the back, until none is left, and run() returns when every call has
// returned, with everything the helpers wrote visible to the caller. Which
// lane runs which k depends on the timing; a task whose calls touch disjoint
// state gives the same result either way.
//
// Between batches the helpers spin (a frame's firmware is a few
// microseconds: waking a sleeping thread costs more than the work),
// offering their core to any other thread that waits for it every
// kSpinsBeforeYield pauses, and after about 1.5 ms without work they sleep
// on a futex until the next batch. The caller never waits for a helper to wake: it takes every k
// itself when none is there, and waits only for calls a helper has begun.
// Nothing allocates after construction. The helpers block every signal, so
// a signal sent to the process interrupts the loop thread's wait.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <thread>
#include <vector>

namespace ecat::slave {

class SpinWorkers {
 public:
  using Task = void (*)(void* context, std::size_t k, unsigned lane) noexcept;
  // A batch holds at most this many calls (the claim word's field).
  static constexpr std::size_t kMaxCount = (std::size_t{1} << 24) - 1;
  // Pause instructions a helper spins through without work before it sleeps:
  // about 1.5 ms on this project's AMD EPYC host (16 k took 0.38 ms), so a
  // helper stays awake across a 1 kHz cycle's idle part and takes its share
  // of the next cycle's first batch (with 16 k it slept every cycle and took
  // half as many words in e2e_firmware_threads).
  static constexpr std::uint32_t kSpinsBeforeSleep = 1u << 16;
  // Pause instructions between two offers of the core (std::this_thread::
  // yield): by a helper without work, and by the caller still waiting for a
  // helper's call (about 25 us here; a firmware call takes a few). Where
  // the host gives the process fewer cores than threads, a spinning helper
  // otherwise kept the loop thread from its core: docs/performance-log.md
  // "Session 23" (taskset -c 0 with BM_Cycle_CspLanes).
  static constexpr std::uint32_t kSpinsBeforeYield = 1u << 10;

  // `helpers` threads besides the caller's (lanes 1..helpers).
  explicit SpinWorkers(unsigned helpers);
  ~SpinWorkers();
  SpinWorkers(const SpinWorkers&) = delete;
  SpinWorkers& operator=(const SpinWorkers&) = delete;

  unsigned lanes() const noexcept { return static_cast<unsigned>(threads_.size()) + 1; }
  // Runs the batch (count <= kMaxCount) as above.
  void run(Task task, void* context, std::size_t count) noexcept;
  // Calls made by the helpers since construction (not by the caller).
  std::uint64_t helped() const noexcept { return helped_.load(std::memory_order_relaxed); }

 private:
  // The claim word: batch number (16 bits), back (24), front (24); the
  // calls not yet claimed are [front, back).
  static constexpr unsigned kFieldBits = 24;
  static constexpr unsigned kBackShift = 24;
  static constexpr unsigned kBatchShift = 48;
  static constexpr std::uint64_t kFieldMask = (std::uint64_t{1} << kFieldBits) - 1;
  static constexpr std::uint64_t kBatchMask = 0xFFFF;
  static std::uint64_t front_of(std::uint64_t c) noexcept { return c & kFieldMask; }
  static std::uint64_t back_of(std::uint64_t c) noexcept { return (c >> kBackShift) & kFieldMask; }

  // Claims a k of the batch in `claim_` and runs it; false when none is
  // left. The caller (lane 0) takes from the front, the helpers from the
  // back: the calls with work tend to be the same batch after batch (the
  // same slaves due), so each tends to stay on one core, its state in that
  // core's cache (measured: docs/performance-log.md "Firmware lanes").
  bool take_one(unsigned lane) noexcept;
  void help(unsigned lane) noexcept;
  void stop_all() noexcept;

  std::vector<std::thread> threads_;
  // Written by run() before the batch is published, read by a lane only
  // after it claimed a k of that batch (run() waits for every such lane).
  Task task_ = nullptr;
  void* context_ = nullptr;
  std::uint64_t batch_ = 0;
  alignas(64) std::atomic<std::uint64_t> claim_{0};
  alignas(64) std::atomic<std::uint32_t> busy_{0};      // helpers inside a batch
  alignas(64) std::atomic<std::uint32_t> sleepers_{0};  // helpers asleep on wake_
  std::atomic<std::uint32_t> wake_{0};
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> helped_{0};
};

}  // namespace ecat::slave
