// What ecat-master does with a segment: bring it from Init to Op the way the
// common masters do (scan, SII, mailbox, PDO sizes over CoE, SM/FMMU set-up,
// optional DC), run the cyclic exchange, and optionally enable and move every
// CiA402 drive in cyclic synchronous position mode.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "apps/ecat-master/cia402_motion.hpp"
#include "apps/ecat-master/pdo_locator.hpp"
#include "common/clock.hpp"
#include "common/expected.hpp"
#include "master/master.hpp"

namespace ecat::app {

struct SessionOptions {
  std::size_t expect_slaves = 0;  // 0: any number
  std::uint64_t cycles = 2000;
  Nanoseconds period = std::chrono::milliseconds(1);
  bool dc = false;
  bool move = false;
  std::int32_t move_distance = 100000;  // increments, CSP ramp
  bool verbose = true;
  bool topology = false;   // print each slave's parent, port and (with dc) delay (topology_report.hpp)
  bool scan_only = false;  // stop after the scan (and the topology print); no state change
};

struct SessionReport {
  std::size_t slaves = 0;
  std::uint64_t cycles = 0;
  std::uint64_t lost_frames = 0;
  std::uint64_t wkc_errors = 0;
  std::uint64_t state_errors = 0;  // AL status checks that found a slave out of Op
  Nanoseconds rtt_median{0};
  Nanoseconds rtt_p99{0};
  Nanoseconds rtt_max{0};
  Nanoseconds jitter_max{0};  // largest deviation of a cycle start from its schedule
  std::vector<std::int32_t> final_positions;  // 6064h per drive after --move
  bool moved_ok = true;
};

// Waits until `deadline` on the session's clock: sleeps on a live clock,
// advances a simulated one. Supplied by the program.
using WaitUntil = std::function<void(Nanoseconds deadline)>;

class Session {
 public:
  Session(master::Master& master, const Clock& clock, WaitUntil wait, SessionOptions options)
      : master_(master), clock_(clock), wait_(std::move(wait)), o_(options) {}

  // Scan to Op. Prints the slaves found when verbose.
  Expected<void, std::string> bring_up();
  // The cyclic exchange (and the motion when asked).
  Expected<SessionReport, std::string> run();

 private:
  Expected<void, std::string> configure_slave(std::size_t i);
  void drive_cycle(std::uint64_t cycle);
  void check_states();

  master::Master& master_;
  const Clock& clock_;
  WaitUntil wait_;
  SessionOptions o_;
  std::vector<PdoLocator> pdos_;
  std::vector<bool> has_coe_;
  std::vector<bool> csp_;  // drive supports cyclic synchronous position
  std::vector<Cia402Motion> motions_;
  SessionReport report_;
};

}  // namespace ecat::app
