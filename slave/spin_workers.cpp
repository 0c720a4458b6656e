#include "slave/spin_workers.hpp"

#include <pthread.h>
#include <signal.h>

#include <string>

namespace ecat::slave {

namespace {

// A spinning thread's hint to the core (and to its sibling hyperthread).
inline void cpu_relax() noexcept {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

}  // namespace

SpinWorkers::SpinWorkers(unsigned helpers) {
  threads_.reserve(helpers);
  // The helpers take no signal: a process-directed one (SIGTERM, SIGUSR1)
  // goes to the loop thread, whose wait it is meant to interrupt. They
  // inherit the mask they are started with; the caller's is restored.
  sigset_t all;
  sigset_t caller;
  sigfillset(&all);
  (void)pthread_sigmask(SIG_SETMASK, &all, &caller);
  try {
    for (unsigned lane = 1; lane <= helpers; ++lane) {
      threads_.emplace_back([this, lane] { help(lane); });
      // A name for top and perf ("ecat-fw1"...).
      const std::string name = "ecat-fw" + std::to_string(lane);
      (void)pthread_setname_np(threads_.back().native_handle(), name.c_str());
    }
  } catch (...) {
    (void)pthread_sigmask(SIG_SETMASK, &caller, nullptr);
    stop_all();  // the ones started (no thread may outlive its object)
    throw;
  }
  (void)pthread_sigmask(SIG_SETMASK, &caller, nullptr);
}

SpinWorkers::~SpinWorkers() { stop_all(); }

void SpinWorkers::stop_all() noexcept {
  stop_.store(true, std::memory_order_seq_cst);
  wake_.fetch_add(1, std::memory_order_seq_cst);
  wake_.notify_all();
  for (std::thread& t : threads_) t.join();
  threads_.clear();
}

void SpinWorkers::run(Task task, void* context, std::size_t count) noexcept {
  if (count == 0) return;
  // No helper is inside a batch here (the last run() waited for them), so
  // these plain writes race with nothing; a helper reads them only after it
  // claimed a k of the batch published below.
  task_ = task;
  context_ = context;
  batch_ = (batch_ + 1) & kBatchMask;
  claim_.store((batch_ << kBatchShift) | (std::uint64_t{count} << kBackShift), std::memory_order_seq_cst);
  // A helper that went to sleep either sees this batch before it waits or
  // is counted in sleepers_ before this load (both sides sequentially
  // consistent), so it is woken.
  if (sleepers_.load(std::memory_order_seq_cst) != 0) {
    wake_.fetch_add(1, std::memory_order_seq_cst);
    wake_.notify_all();
  }
  while (take_one(0)) {
  }
  // Every k is claimed. A helper that claimed one raised busy_ before its
  // claim, which this thread's last load of claim_ saw: it is counted here
  // until its call has returned.
  // A call takes microseconds; a helper still busy after kSpinsBeforeYield
  // pauses was most likely preempted inside it (a host with fewer free cores
  // than threads): the caller lets the scheduler run it instead of spinning
  // out its own time slice.
  for (std::uint32_t spins = 0; busy_.load(std::memory_order_seq_cst) != 0;) {
    if (++spins < kSpinsBeforeYield) {
      cpu_relax();
    } else {
      std::this_thread::yield();
    }
  }
}

bool SpinWorkers::take_one(unsigned lane) noexcept {
  const bool from_back = lane != 0;
  std::uint64_t c = claim_.load(std::memory_order_seq_cst);
  while (front_of(c) < back_of(c)) {
    const std::uint64_t claimed = from_back ? c - (std::uint64_t{1} << kBackShift) : c + 1;
    if (claim_.compare_exchange_weak(c, claimed, std::memory_order_seq_cst)) {
      task_(context_, static_cast<std::size_t>(from_back ? back_of(c) - 1 : front_of(c)), lane);
      return true;
    }
  }
  return false;
}

void SpinWorkers::help(unsigned lane) noexcept {
  std::uint32_t idle = 0;
  while (!stop_.load(std::memory_order_relaxed)) {
    std::uint64_t c = claim_.load(std::memory_order_relaxed);
    if (front_of(c) < back_of(c)) {
      busy_.fetch_add(1, std::memory_order_seq_cst);
      std::uint64_t done = 0;
      while (take_one(lane)) ++done;
      busy_.fetch_sub(1, std::memory_order_seq_cst);
      helped_.fetch_add(done, std::memory_order_relaxed);
      idle = 0;
      continue;
    }
    if (++idle < kSpinsBeforeSleep) {
      // Now and then the core is offered to another thread that may be
      // waiting for it (the loop thread, where the host gives the process
      // fewer cores than threads); with none, the yield returns at once.
      if (idle % kSpinsBeforeYield == 0) {
        std::this_thread::yield();
      } else {
        cpu_relax();
      }
      continue;
    }
    const std::uint32_t seen = wake_.load(std::memory_order_seq_cst);
    sleepers_.fetch_add(1, std::memory_order_seq_cst);
    c = claim_.load(std::memory_order_seq_cst);
    if (front_of(c) >= back_of(c) && !stop_.load(std::memory_order_seq_cst)) {
      wake_.wait(seen, std::memory_order_seq_cst);
    }
    sleepers_.fetch_sub(1, std::memory_order_seq_cst);
    idle = 0;
  }
}

}  // namespace ecat::slave
