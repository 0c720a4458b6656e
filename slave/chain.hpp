// A line of virtual slaves in one process, wired port 0 -> port 1 as real
// slaves are (esc::Segment), with the firmware of a slave run after a frame
// when its ESC raised the IRQ or its own deadline is due. This is what ecat-slave serves on a wire and what tests
// and the demo drive in-process.
#pragma once

#include <cstdio>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "common/clock.hpp"
#include "common/expected.hpp"
#include "esc/dc/vcd_trace.hpp"
#include "esc/segment.hpp"
#include "slave/cycle_timing.hpp"
#include "slave/frame_age.hpp"
#include "slave/slave_stats.hpp"
#include "slave/spin_workers.hpp"
#include "slave/virtual_slave.hpp"
#include "slave/wake_times.hpp"

namespace ecat::slave {

class Chain {
 public:
  explicit Chain(const Clock& clock) : clock_(clock) {}
  Chain(const Chain&) = delete;
  Chain& operator=(const Chain&) = delete;

  // Appends a slave at the end of the line (set-up only).
  Expected<void, std::string> add(od::DeviceDescription device, const SlaveOptions& options);
  // The same with a description shared by several slaves (issue 16: one
  // copy of the dictionary, names and SII for a thousand drives of a type).
  Expected<void, std::string> add(std::shared_ptr<const od::DeviceDescription> device, const SlaveOptions& options);
  // Adds a slave whose port `port` is cabled to port `parent_port` of slave
  // `parent` (an earlier index): trees of couplers and junctions (set-up
  // only; esc::Segment::add). `delay`: that cable's delay (default: the
  // segment's hop delay), as the DC receive times see it.
  Expected<void, std::string> attach(od::DeviceDescription device, const SlaveOptions& options, std::size_t parent,
                                     unsigned parent_port, unsigned port = esc::kUpstreamPort,
                                     std::optional<Nanoseconds> delay = std::nullopt);
  // The same with a description shared by several slaves.
  Expected<void, std::string> attach(std::shared_ptr<const od::DeviceDescription> device, const SlaveOptions& options,
                                     std::size_t parent, unsigned parent_port, unsigned port = esc::kUpstreamPort,
                                     std::optional<Nanoseconds> delay = std::nullopt);
  // Cables the master's redundant port (1) to port `port` of slave `slave`:
  // the far end of a ring (set-up only).
  Expected<void, std::string> connect_redundant(std::size_t slave, unsigned port);

  // Carries `frame` (a whole Ethernet frame) through the line at `now`, in
  // place, then lets each slave's firmware react. Returns true when the frame
  // comes back to the master (send it), false when it is malformed or lost.
  bool process_frame(std::span<std::uint8_t> frame, Nanoseconds now) noexcept;
  // process_frame in two halves, for a live wire: pass_frame() is what the
  // ESCs do while the frame streams through (send the frame as soon as it
  // returns true), run_firmware() is each slave's interrupt handler that
  // runs afterwards on the µC, off the frame's round trip.
  bool pass_frame(std::span<std::uint8_t> frame, Nanoseconds now) noexcept {
    return pass_frame_on(frame, now, 0).returned();
  }
  // pass_frame for a frame that arrived on master port `master_port` (0, or
  // 1 for the redundant one); says on which master port it leaves.
  esc::Delivery pass_frame_on(std::span<std::uint8_t> frame, Nanoseconds now, unsigned master_port) noexcept;
  void run_firmware(Nanoseconds now) noexcept;

  // The firmware on more than one core (issue 30 item 3, docs/performance-log.md
  // "Firmware lanes"): run_firmware and the due polls hand the slaves with
  // work to `threads` threads, this one and threads - 1 helpers that spin
  // between frames (they sleep after about 1.5 ms without work). A slave's
  // firmware touches only its own ESC and objects, so the frames, registers
  // and times are those of one thread (tests/slave/chain_lanes_test.cpp).
  // Only a run with at least `min_slaves` candidates pending or due by time
  // in at least two 64-slave words is split; the helpers take whole words,
  // so the bits and times the chain keeps per word are written by one
  // thread. The firmware stays on this thread while a slave writes outside
  // itself: a VCD trace (open_trace), an external firmware, an SPI PDI, an
  // EoE report callback, or a fault that reaches back into its catalogue
  // (keep_firmware_serial).
  // 1: no helper (the default: the helpers spin, so the CPU time grows and
  // only the wall time can shrink). Fails when a thread cannot be started.
  // kMinSplitSlaves: measured (docs/performance-log.md "Firmware lanes"): with
  // the cores close (a cache line there and back in ~100-200 ns) the SYNC0
  // run of 100 drives split gives 0.91x the cycle, with them far apart
  // (~400 ns) 2.4x; at 1000 drives 0.74x against 1.1-1.3x. Below ~200 busy
  // slaves the possible gain is too small for the possible loss.
  static constexpr std::size_t kMinSplitSlaves = 192;
  Expected<void, std::string> set_firmware_threads(unsigned threads, std::size_t min_slaves = kMinSplitSlaves);
  unsigned firmware_threads() const noexcept { return lanes_ ? lanes_->lanes() : 1; }
  // From now on every slave's firmware runs on this thread (see above).
  void keep_firmware_serial() noexcept {
    serial_forced_ = true;
    split_ok_ = false;
  }
  // Whether keep_firmware_serial was called (ecat-slave's statistics say so).
  bool firmware_kept_serial() const noexcept { return serial_forced_; }
  // Paused, every run stays on this thread (the helpers go to sleep after
  // their idle spin) until resumed; the frames are the same either way. The
  // --firmware-threads auto judge (slave/lane_judge.hpp) switches it.
  // Resuming takes effect at the next run, which asks every slave once (a
  // rescan: the split's conditions are checked again there).
  void pause_split(bool paused) noexcept;
  bool split_paused() const noexcept { return split_paused_; }
  // Whether every slave's firmware may run on any thread (VirtualSlave::
  // runs_apart; slave/lane_choice.hpp asks before it chooses two).
  bool slaves_run_apart() const noexcept;
  // The runs (after a frame, or a due poll's batch) split over the lanes.
  std::uint64_t split_runs() const noexcept { return split_runs_; }
  // The candidates the helpers took (not this thread): SpinWorkers::helped.
  std::uint64_t helped_words() const noexcept { return lanes_ ? lanes_->helped() : 0; }

  // Skipping (issue 16 item 5, docs/esc.md): frames enter only the ESCs
  // they address or that are not passive, and run_firmware asks only the
  // slaves that may be due. Off: every ESC entered, every slave asked (the
  // reference the tests compare with). On by default.
  void set_skipping(bool on) noexcept {
    segment_.set_skipping(on);
    ask_all_ = !on;
    poll_all_ = !on;
    rescan_ = rescan_ || on;  // the times untracked meanwhile are taken anew
  }
  // Polling only the due slaves (docs/e2e.md "Live timing"): poll() and
  // catch_up() poll the slaves whose time came (VirtualSlave::visit_at, as
  // the slave's last note left it: after its poll, a frame that entered its
  // ESC, or any access to the ESC from outside a frame) and the pending
  // ones; every other slave's poll would only note the time. Off: every
  // slave polled, the reference tests/slave/chain_poll_test.cpp compares
  // with (bytes, registers, event times). On by default; set_skipping(false)
  // turns it off too.
  void set_polling_due(bool on) noexcept {
    poll_all_ = !on;
    rescan_ = rescan_ || on;
  }

  // Fewer slaves than kTrackFrom: every slave is asked after every frame,
  // as with skipping off, a poll reads each slave's visit time from the
  // slave itself (set_polling_due(false): polls every one), and nothing is
  // noted.
  // Keeping the pending bits and wake times costs more (noting, the due
  // sets, the touched scan) than asking a slave that is not due, a few
  // loads (issue 30: the one-drive cycle 3,705 -> 3,474 instructions, 3,333
  // at 49fab26; the ten-drive cycle 31,956 -> 30,966 at 16 against 4);
  // the segment still skips from esc::Segment::kSkipFrom ESCs on, and
  // asking every slave is a superset of asking the entered ones.
  static constexpr std::size_t kTrackFrom = 16;

  // Timers and firmware of the slaves (see set_polling_due); returns the
  // earliest next deadline of all, as a poll of every slave would.
  std::optional<Nanoseconds> poll(Nanoseconds now) noexcept { return deadline_or_none(advance(now)); }
  // The same as a time, kNoDeadline when none.
  Nanoseconds advance(Nanoseconds now) noexcept;

  // Live runs, where the process may be woken late (issue 19): the time at
  // which to process a frame that the medium says arrived at `arrival`
  // (nullopt: not known) while the clock reads `now`. It is the arrival,
  // kept within [the latest time the chain has seen, now] so the chain's time
  // never runs backwards, and the timers due by then run first: a SYNC0 that
  // fell before the frame arrived is seen before it, one that fell after is
  // not. Pass the frame and run the firmware at the time returned.
  Nanoseconds catch_up(std::optional<Nanoseconds> arrival, Nanoseconds now) noexcept;
  // A frame taken from a live medium (issue 29 item 4): nullopt when it
  // waited longer than the max frame age since `arrival` (frame_is_stale):
  // it is lost on the wire - do not pass it, do not answer it; it is counted
  // in stats().frames_stale and nothing else changes (not the chain's time,
  // not a timer, not an ESC). Otherwise catch_up(arrival, now): the time to
  // pass the frame and run the firmware at.
  std::optional<Nanoseconds> admit(std::optional<Nanoseconds> arrival, Nanoseconds now) noexcept;
  // The age limit admit() applies; 0 (a Chain's default): none. ecat-slave
  // sets kDefaultMaxFrameAge unless --max-frame-age says otherwise.
  void set_max_frame_age(Nanoseconds max_age) noexcept { max_frame_age_ = max_age; }
  Nanoseconds max_frame_age() const noexcept { return max_frame_age_; }
  // The latest time the chain has been polled or has passed a frame at.
  Nanoseconds time_seen() const noexcept { return seen_; }

  std::size_t size() const noexcept { return slaves_.size(); }
  // A slave handed out may be changed: the next run_firmware asks every slave.
  VirtualSlave& operator[](std::size_t i) noexcept {
    rescan_ = true;
    return *slaves_[i];
  }
  const VirtualSlave& operator[](std::size_t i) const noexcept { return *slaves_[i]; }
  esc::Segment& segment() noexcept {
    rescan_ = true;
    return segment_;
  }
  const esc::Segment& segment() const noexcept { return segment_; }
  const ChainStats& stats() const noexcept { return stats_; }
  // The master's cycle as the returned process-data frames show it
  // (settle() it on the loop thread before reading).
  CycleTiming& cycle_timing() noexcept { return cycle_timing_; }
  const CycleTiming& cycle_timing() const noexcept { return cycle_timing_; }

  // VCD trace of every slave's SYNC pulses, SM events, application cycle and
  // ESM state (set-up, after the last add()).
  Expected<void, std::string> open_trace(const std::string& path);
  // SVG plot of the first drive's motion trace.
  Expected<void, std::string> write_plot(const std::string& path) const;
  // Ends the run: flushes and closes the VCD trace; an error names the file
  // (a short or failed write included).
  Expected<void, std::string> shutdown() noexcept;

 private:
  [[gnu::always_inline]] inline void count_returned(std::span<const std::uint8_t> frame, Nanoseconds now) noexcept;
  void added() noexcept;
  // Where after_frame and note keep a slave's wake time and deadline: in
  // the WakeTimes directly, or (a lane of a split run) apart, with the
  // bounds merged when every lane is done.
  struct DirectNotes {
    static void set(Chain& c, std::size_t i, Nanoseconds wake, Nanoseconds deadline) noexcept {
      c.wakes_.set(i, wake);
      c.deadlines_.set(i, deadline);
    }
  };
  struct alignas(64) ApartNotes {  // one lane's, on a line of its own
    WakeTimes::Bound wake_bound;
    WakeTimes::Bound deadline_bound;
    void set(Chain& c, std::size_t i, Nanoseconds wake, Nanoseconds deadline) noexcept {
      c.wakes_.set_apart(i, wake, wake_bound);
      c.deadlines_.set_apart(i, deadline, deadline_bound);
    }
  };
  // Runs slave i's firmware if a frame left it work; keeps what it waits for.
  template <class Notes>
  void after_frame(std::size_t i, Nanoseconds now, Notes& notes) noexcept;
  // Keeps slave i's pending bit, its wake time and its next deadline, and
  // takes in its ESC's accesses so far (esc::Esc::take_in_accesses).
  template <class Notes>
  void note(std::size_t i, Notes& notes) noexcept;
  void note(std::size_t i) noexcept {
    DirectNotes direct;
    note(i, direct);
  }
  // A rescan is done: what run_firmware keeps is taken anew, and whether
  // the firmware may be split is decided again.
  void rescanned() noexcept;
  // run_firmware's and poll_due's candidates on the lanes when worth it
  // (false: not split, the one-thread loop takes them; out of line).
  [[gnu::noinline]] bool run_firmware_split(Nanoseconds now) noexcept;
  [[gnu::noinline]] bool poll_due_split(Nanoseconds now, bool next, Nanoseconds& earliest) noexcept;
  // Whether the candidates in due_, `busy` of them pending or due by time,
  // are worth splitting; lists their words.
  bool plan_split(std::size_t busy) noexcept;
  // Runs `task` over the listed words on the lanes, then merges the bounds.
  void run_lanes(SpinWorkers::Task task, Nanoseconds now) noexcept;
  // The lanes' tasks, each for the candidates of word split_words_[k]:
  // run_firmware's after_frame; poll_due's poll, then its note.
  static void run_word(void* chain, std::size_t k, unsigned lane) noexcept;
  static void poll_word(void* chain, std::size_t k, unsigned lane) noexcept;
  static void note_word(void* chain, std::size_t k, unsigned lane) noexcept;
  // poll() of every slave, and of the due ones (set_polling_due); the
  // latter computes the earliest deadline only when `next` is wanted.
  // Each returns the earliest deadline, kNoDeadline when none (no optional
  // returned through a call: common/clock.hpp).
  Nanoseconds poll_every(Nanoseconds now) noexcept;
  // One of them, as the modes say (`next`: poll_due's).
  Nanoseconds poll_at(Nanoseconds now, bool next) noexcept;
  Nanoseconds poll_due(Nanoseconds now, bool next) noexcept;
  // Notes again the slaves changed since their last note other than by this
  // chain's polls and firmware runs: a frame entered their ESC (before
  // run_firmware saw it) or anything accessed it from outside a frame after
  // that note (a PDI host, a fault, a test: in the segment's dirty set and
  // esc::Esc::accessed, which a note clears).
  void note_touched() noexcept;
  std::uint8_t next_colour() const noexcept;

  const Clock& clock_;
  std::vector<std::unique_ptr<VirtualSlave>> slaves_;
  struct FileCloser {
    void operator()(std::FILE* f) const noexcept { std::fclose(f); }
  };
  std::unique_ptr<std::FILE, FileCloser> trace_file_;
  std::string trace_path_;
  std::unique_ptr<esc::VcdTrace> trace_;
  esc::Segment segment_;
  ChainStats stats_;
  Nanoseconds seen_{Nanoseconds::min()};
  Nanoseconds max_frame_age_{0};
  // Which slaves run_firmware asks (issue 16 item 5): the ones whose ESC a
  // frame entered (esc::Segment::entered), the pending ones (bit i of word
  // i / 64: VirtualSlave::pending() when last asked), and the ones whose
  // wake_at() (as last asked, in wakes_) has come (due_: this call's).
  std::vector<std::uint64_t> pending_;
  std::vector<std::uint64_t> due_;
  WakeTimes wakes_;
  // Per slave: what its poll would return now (VirtualSlave::next_deadline
  // at its last note); their earliest is what poll() returns.
  WakeTimes deadlines_;
  bool split_ok_ = false;  // lanes_ and slaves_run_apart() at the last rescan
  bool rescan_ = true;  // every slave next time (set-up, poll, a slave handed out)
  bool ask_all_ = false;  // set_skipping(false)
  bool poll_all_ = false;  // set_polling_due(false)
  bool small_ = true;  // slaves_.size() < kTrackFrom
  // Last: its interval ring (8 KiB) between the segment and the fields
  // above put them 8 KiB apart, where a store to one and a load of the
  // other can be taken for the same address (the low 12 bits match) and
  // the load waits; with 24 bytes more in the segment the one-drive cycle
  // took 1.2x its time (issue 30, docs/performance-log.md session 16).
  CycleTiming cycle_timing_;
  // The firmware lanes (set_firmware_threads), after the hot fields: null
  // with one thread.
  std::unique_ptr<SpinWorkers> lanes_;
  std::vector<ApartNotes> lane_notes_;      // per lane
  std::vector<std::uint32_t> split_words_;  // a split run's words with candidates
  std::size_t min_split_ = kMinSplitSlaves;
  std::uint64_t split_runs_ = 0;
  Nanoseconds split_now_{0};
  bool serial_forced_ = false;  // keep_firmware_serial
  bool split_paused_ = false;   // pause_split
  // Every slave asked and polled every time: nothing reads the pending
  // bits and times, so they are not kept (BM_Cycle_CspFullPass).
  bool untracked() const noexcept { return ask_all_ && poll_all_; }
};

}  // namespace ecat::slave
