// A chain of virtual slaves (slave::Chain) behind the in-memory transport on a
// manual clock that advances 50 µs per frame: the master talks to the real
// ESC, ESM and CoE stack in one process.
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <string>

#include "esi/device_loader.hpp"
#include "master/master.hpp"
#include "slave/chain.hpp"
#include "transport/in_memory_transport.hpp"

namespace ecat::master::test {

inline std::string device_path(const char* name) { return std::string(ECAT_SOURCE_DIR) + "/xml/devices/" + name; }

class InProcessBus {
 public:
  static constexpr Nanoseconds kFrameTime{50'000};

  InProcessBus() : chain_(clock), transport([this](Bytes f) {
                     if (!chain_.process_frame(f, clock.now())) transport.drop_next(1);
                     if (after_frame) after_frame();
                     clock.advance(kFrameTime);
                   }) {}

  ::testing::AssertionResult add(const std::string& file, int count = 1,
                                 slave::PdiKind pdi = slave::PdiKind::Direct, const slave::SlaveOptions& base = {}) {
    for (int i = 0; i < count; ++i) {
      auto dev = esi::load_device_file(file);
      if (!dev) return ::testing::AssertionFailure() << dev.error().to_string();
      slave::SlaveOptions o = base;
      o.name = "slave-" + std::to_string(i + 1);
      o.pdi = pdi;
      if (auto r = chain_.add(std::move(*dev), o); !r) return ::testing::AssertionFailure() << r.error();
    }
    return ::testing::AssertionSuccess();
  }

  void wait(Nanoseconds d) {
    const Nanoseconds end = clock.now() + d;
    while (clock.now() < end) {
      (void)chain_.poll(clock.now());
      clock.advance(std::min(Nanoseconds{1'000'000}, end - clock.now()));
    }
    (void)chain_.poll(clock.now());
  }

  slave::Chain& chain() { return chain_; }

  ManualClock clock;
  // Runs after the slaves' firmware handled each frame: a test-made firmware
  // fault that rewrites what the µC left in the ESC (AL status, code).
  std::function<void()> after_frame;

 private:
  slave::Chain chain_;

 public:
  transport::InMemoryTransport transport;
};

}  // namespace ecat::master::test
