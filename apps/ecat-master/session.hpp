// What ecat-master does with a segment: bring it from Init to Op the way the
// common masters do (scan, SII, mailbox, PDO sizes over CoE, SM/FMMU set-up,
// optional DC), run the cyclic exchange, and optionally enable and move every
// CiA402 drive in cyclic synchronous position mode.
#pragma once

#include <csignal>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "apps/ecat-master/cia402_motion.hpp"
#include "apps/ecat-master/lateness.hpp"
#include "apps/ecat-master/pdo_locator.hpp"
#include "common/clock.hpp"
#include "common/expected.hpp"
#include "master/dc_phase.hpp"
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
  // With dc: the cyclic frame reaches the reference clock this long before
  // each SYNC0 (master/dc_phase.hpp); negative = half the period; 0 = no
  // phase lock (a fixed schedule from the first cycle, as before issue 19).
  Nanoseconds dc_lead{-1};
  // Acknowledge a slave that left Op with an error and bring it back (as
  // SOEM's ec_sample does), checking every 100 cycles instead of 500.
  bool recover = false;
  bool topology = false;   // print each slave's parent, port and (with dc) delay (topology_report.hpp)
  bool scan_only = false;  // stop after the scan (and the topology print); no state change
  // --sdo-read: objects uploaded from every CoE slave in PreOp and printed
  // ("slave N sdo IIIIh:SS = bytes"), e.g. to check a firmware's dictionary.
  std::vector<std::pair<std::uint16_t, std::uint8_t>> sdo_reads;
  // Set to non-zero (by a signal handler: SIGINT, SIGTERM) to end run()
  // before its next cycle; the report then covers the cycles run so far.
  // Null: every one of `cycles` runs.
  const volatile std::sig_atomic_t* stop = nullptr;
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
  LatenessHistogram lateness;  // every cycle's wake-up minus its scheduled time
  std::uint64_t skipped_slots = 0;  // fixed schedule: periods skipped after a stall
  // DC phase lock (run() only, after its acquisition): arrival at the
  // reference minus the target (SYNC0 - lead), and SYNC0 events no frame fed.
  bool phase_locked = false;
  Nanoseconds phase_error_p99{0};  // of |error|
  Nanoseconds phase_error_max{0};
  Nanoseconds margin_min{0};       // smallest time from a frame's arrival to its SYNC0
  std::uint64_t sync0_without_frame = 0;
  // --recover: per slave, how often it was found in an error state and acknowledged, and its last code.
  std::vector<std::uint32_t> left_op;
  std::vector<std::uint16_t> last_code;
  // --recover: per slave, how often it came back fresh at its position (a
  // power cycle) and was addressed and configured again (hot connect).
  std::vector<std::uint32_t> reconnected;
  std::vector<std::int32_t> final_positions;  // 6064h per drive after --move
  bool moved_ok = true;
  bool stopped = false;  // run() ended before `cycles` because `stop` was set
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
  // The longest time between two cycles of the start-up (SafeOp warm-up,
  // Op request): more than a period means the master itself let a SYNC0 pass
  // without a frame. Printed when the start-up fails, so a DC slave's refusal
  // of Op (001Ah) can be told a late master's doing (docs/e2e.md "Live
  // timing under load").
  Nanoseconds startup_gap_max() const noexcept { return startup_gap_max_; }

 private:
  // `again`: a hot connect (the SDO reads of --sdo-read are not repeated).
  Expected<void, std::string> configure_slave(std::size_t i, bool again = false);
  // --recover for a slave that no longer answers at its station address.
  void reconnect(std::size_t i);
  void drive_cycle(std::uint64_t cycle);
  void check_states();
  // Waits for the next cycle (the phase lock's send time, else the fixed
  // schedule), records the lateness, exchanges the frame, feeds the lock.
  Expected<master::CyclicResult, master::MasterError> cycle_exchange();
  Expected<void, std::string> request_op_cycling();

  master::Master& master_;
  const Clock& clock_;
  WaitUntil wait_;
  SessionOptions o_;
  std::vector<PdoLocator> pdos_;
  std::vector<bool> has_coe_;
  std::vector<bool> csp_;  // drive supports cyclic synchronous position
  std::vector<Cia402Motion> motions_;
  SessionReport report_;
  std::optional<master::DcPhaseLock> phase_;
  Nanoseconds next_fixed_{-1};  // fixed schedule: next cycle's time (-1: not started)
  bool record_lateness_ = false;
  Nanoseconds startup_gap_max_{0};
  std::optional<Nanoseconds> last_send_;  // when the previous cycle's frame went out
};

}  // namespace ecat::app
