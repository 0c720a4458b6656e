// A master and a chain of virtual slaves in one process on simulated time:
// the in-memory transport hands every frame to the chain, which advances the
// clock by a fixed wire time per frame.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/clock.hpp"
#include "esi/device_loader.hpp"
#include "master/coe_client.hpp"
#include "master/master.hpp"
#include "slave/chain.hpp"
#include "transport/in_memory_transport.hpp"

namespace ecat::test {

inline constexpr Nanoseconds kWireTime = std::chrono::microseconds(5);

// The chain's view of the simulated clock, with its reads counted (how
// often the slaves read the time: a live run's clock costs a vDSO call a read).
class CountedClock final : public Clock {
 public:
  explicit CountedClock(const Clock& clock) noexcept : clock_(clock) {}
  Nanoseconds now() const noexcept override {
    ++reads_;
    return clock_.now();
  }
  std::uint64_t reads() const noexcept { return reads_; }

 private:
  const Clock& clock_;
  mutable std::uint64_t reads_ = 0;
};

struct InProcess {
  ManualClock clock;
  CountedClock chain_clock{clock};
  slave::Chain chain{chain_clock};
  transport::InMemoryTransport wire{[this](Bytes frame) {
    clock.advance(kWireTime);
    (void)chain.process_frame(frame, clock.now());
  }};
  master::Master master{wire, clock};

  void add(od::DeviceDescription d, slave::SlaveOptions o = {}) {
    auto ok = chain.add(std::move(d), o);
    if (!ok) throw std::runtime_error(ok.error());
  }
  void add_default(std::size_t n = 1) {
    auto d = esi::load_default_device();
    if (!d) throw std::runtime_error(d.error().to_string());
    for (std::size_t i = 0; i < n; ++i) add(*d);
  }
  // Lets simulated time pass with the slaves' timers and firmware running.
  void advance(Nanoseconds d) {
    clock.advance(d);
    (void)chain.poll(clock.now());
  }

  // The standard start-up (masters.md §1): scan, mailbox, PDO sizes read
  // over SDO, SM/FMMU set-up, PreOp -> SafeOp (with valid outputs) -> Op.
  // Returns "" on success or what failed.
  std::string bring_up(Nanoseconds cycle = std::chrono::milliseconds(1)) {
    auto n = master.scan();
    if (!n) return "scan";
    for (std::size_t i = 0; i < *n; ++i) {
      if (!master.configure_mailbox(i)) return "mailbox";
      auto st = master.request_state(i, master::AlState::PreOp);
      if (!st || st->error()) return "preop";
      master::CoeClient coe(master, i);
      if (!coe.read_pdo_sizes()) return "pdo sizes";
    }
    if (!master.configure_process_data()) return "process data";
    for (std::size_t i = 0; i < *n; ++i) {
      auto st = master.request_state(i, master::AlState::SafeOp);
      if (!st || st->error()) return "safeop";
    }
    for (int c = 0; c < 10; ++c) cycle_once(cycle);
    for (std::size_t i = 0; i < *n; ++i) {
      auto st = master.request_state(i, master::AlState::Op);
      if (!st || st->error()) return "op";
    }
    return "";
  }

  // One master cycle: wait a period, exchange process data.
  Expected<master::CyclicResult, master::MasterError> cycle_once(Nanoseconds cycle) {
    advance(cycle);
    return master.exchange_process_data();
  }
};

}  // namespace ecat::test
