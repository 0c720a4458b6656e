// The firmware of a chain's slaves on two threads (issue 30 item 3,
// slave::Chain::set_firmware_threads) against the same chain on one: the
// project's master takes both through scan, SII, mailbox/SDO, PreOp, SafeOp
// and Op and cycles process data; every frame that comes back, every ESC's
// memory and times and every slave's state at the end are the same. Then
// what keeps the firmware on the loop thread.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <optional>
#include <vector>

#include "master/coe_client.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

// Two 64-slave words and a part of a third: every frame that enters them
// all (a broadcast, the process data) is split.
constexpr std::size_t kDrives = 130;

// A chain of kDrives default drives with its firmware on `threads` threads
// (split from `min_slaves` candidates) and the project's master, which
// keeps every frame that came back.
struct Recorded {
  explicit Recorded(unsigned threads, std::size_t min_slaves = 1) {
    auto ok = chain.set_firmware_threads(threads, min_slaves);
    if (!ok) throw std::runtime_error(ok.error());
    auto d = esi::load_default_device();
    if (!d) throw std::runtime_error(d.error().to_string());
    auto shared = std::make_shared<const od::DeviceDescription>(std::move(*d));
    for (std::size_t i = 0; i < kDrives; ++i) {
      if (auto a = chain.add(shared, {}); !a) throw std::runtime_error(a.error());
    }
  }
  // Scan, mailboxes, PreOp, PDO sizes, process data, SafeOp, Op: "" or what failed.
  std::string bring_up() {
    if (master.scan().value_or(0) != kDrives) return "scan";
    if (master.configure_mailboxes().value_or(0) != kDrives) return "mailboxes";
    if (!master.request_state_all(master::AlState::PreOp)) return "preop";
    std::vector<std::size_t> all(kDrives);
    for (std::size_t i = 0; i < kDrives; ++i) all[i] = i;
    if (!master::read_pdo_sizes_all(master, all)) return "pdo sizes";
    if (!master.configure_process_data()) return "process data";
    if (!master.request_state_all(master::AlState::SafeOp)) return "safeop";
    for (int c = 0; c < 10; ++c) (void)cycle();
    if (!master.request_state_all(master::AlState::Op)) return "op";
    return "";
  }
  bool cycle() {
    clock.advance(std::chrono::milliseconds(1));
    (void)chain.poll(clock.now());
    auto r = master.exchange_process_data();
    return r && r->ok();
  }

  ManualClock clock;
  slave::Chain chain{clock};
  std::vector<std::vector<std::uint8_t>> frames;
  transport::InMemoryTransport wire{[this](Bytes frame) {
    clock.advance(kWireTime);
    (void)chain.process_frame(frame, clock.now());
    frames.emplace_back(frame.begin(), frame.end());
  }};
  master::Master master{wire, clock, [] {
                          master::MasterConfig c;
                          c.max_slaves = kDrives;
                          return c;
                        }()};
};

TEST(ChainLanes, TwoThreadsGiveTheFramesRegistersAndTimesOfOne) {
  Recorded lanes(2);
  Recorded ref(1);
  ASSERT_EQ(lanes.chain.firmware_threads(), 2u);
  ASSERT_EQ(ref.chain.firmware_threads(), 1u);
  for (Recorded* r : {&lanes, &ref}) {
    ASSERT_EQ(r->bring_up(), "");
    for (int c = 0; c < 100; ++c) ASSERT_TRUE(r->cycle()) << "cycle " << c;
  }
  // The master stops: every process-data watchdog (100 ms) expires at the
  // same time, and the poll that finds them (all 130 due) is split - its
  // polls, then its notes. Then the master reads the errors.
  const std::uint64_t splits_before = lanes.chain.split_runs();
  std::vector<std::optional<Nanoseconds>> next_lanes;
  std::vector<std::optional<Nanoseconds>> next_ref;
  for (Recorded* r : {&lanes, &ref}) {
    auto& next = r == &lanes ? next_lanes : next_ref;
    r->clock.advance(std::chrono::milliseconds(200));
    next.push_back(r->chain.poll(r->clock.now()));
    // What each poll returns (the earliest deadline) until the master is back.
    for (int t = 0; t < 50; ++t) {
      r->clock.advance(std::chrono::microseconds(250));
      next.push_back(r->chain.poll(r->clock.now()));
    }
    for (int c = 0; c < 3; ++c) (void)r->cycle();
  }
  EXPECT_EQ(next_lanes, next_ref);
  EXPECT_GE(lanes.chain.split_runs(), splits_before + 2);
  EXPECT_EQ(lanes.chain[kDrives - 1].status().state, esc::AlState::SafeOp);
  EXPECT_TRUE(lanes.chain[kDrives - 1].status().error);
  ASSERT_EQ(lanes.frames.size(), ref.frames.size());
  for (std::size_t k = 0; k < lanes.frames.size(); ++k) {
    ASSERT_EQ(lanes.frames[k], ref.frames[k]) << "frame " << k;
  }
  for (std::size_t i = 0; i < kDrives; ++i) {
    const esc::Esc& x = lanes.chain[i].esc();
    const esc::Esc& y = ref.chain[i].esc();
    EXPECT_EQ(std::memcmp(x.memory(), y.memory(), x.memory_size()), 0) << "slave " << i;
    EXPECT_EQ(x.last_time(), y.last_time()) << "slave " << i;
    EXPECT_EQ(x.next_timer(), y.next_timer()) << "slave " << i;
    const slave::SlaveStatus a = lanes.chain[i].status();
    const slave::SlaveStatus b = ref.chain[i].status();
    EXPECT_EQ(a.state, b.state) << "slave " << i;
    EXPECT_EQ(a.application_cycles, b.application_cycles) << "slave " << i;
    EXPECT_EQ(a.firmware_polls, b.firmware_polls) << "slave " << i;
  }
  // Split: every cycle's process data at least (which lane took which word
  // depends on the host's timing: counted, not asserted).
  EXPECT_GE(lanes.chain.split_runs(), 100u);
  EXPECT_EQ(ref.chain.split_runs(), 0u);
  std::printf("split runs %llu, words the helper took %llu\n",
              static_cast<unsigned long long>(lanes.chain.split_runs()),
              static_cast<unsigned long long>(lanes.chain.helped_words()));
}

// Below the threshold of candidates a run stays on the loop thread.
TEST(ChainLanes, FewCandidatesAreNotSplit) {
  Recorded p(2, kDrives + 1);
  ASSERT_EQ(p.bring_up(), "");
  EXPECT_EQ(p.chain.split_runs(), 0u);
  EXPECT_EQ(p.chain[kDrives - 1].status().state, esc::AlState::Op);
}

// A VCD trace writes one file for every slave: no split while it is open;
// neither after keep_firmware_serial (a fault's ESM guard).
TEST(ChainLanes, ATraceOrASerialFaultKeepsTheFirmwareOnTheLoopThread) {
  const std::string path =
      (std::filesystem::temp_directory_path() / ("chain-lanes-" + std::to_string(::getpid()) + ".vcd")).string();
  {
    Recorded p(2);
    ASSERT_TRUE(p.chain.open_trace(path));
    ASSERT_EQ(p.bring_up(), "");
    EXPECT_EQ(p.chain.split_runs(), 0u);
    ASSERT_TRUE(p.chain.shutdown());
  }
  std::filesystem::remove(path);
  Recorded p(2);
  p.chain.keep_firmware_serial();
  ASSERT_EQ(p.bring_up(), "");
  EXPECT_EQ(p.chain.split_runs(), 0u);
}

// pause_split (the --firmware-threads auto judge, slave/lane_judge.hpp):
// paused, no run is split; resumed, they are again; and the frames, ESC
// memory and states through pauses and resumes mid-run are those of one
// thread.
TEST(ChainLanes, APausedSplitRunsOnTheLoopThreadAndResumesWithTheSameFrames) {
  Recorded lanes(2);
  Recorded ref(1);
  lanes.chain.pause_split(true);
  EXPECT_TRUE(lanes.chain.split_paused());
  for (Recorded* r : {&lanes, &ref}) ASSERT_EQ(r->bring_up(), "");
  EXPECT_EQ(lanes.chain.split_runs(), 0u);
  std::uint64_t splits = 0;
  for (int round = 0; round < 5; ++round) {
    const bool paused = round % 2 == 1;
    lanes.chain.pause_split(paused);
    for (Recorded* r : {&lanes, &ref}) {
      for (int c = 0; c < 20; ++c) ASSERT_TRUE(r->cycle()) << "round " << round << " cycle " << c;
    }
    if (paused) {
      EXPECT_EQ(lanes.chain.split_runs(), splits) << "round " << round;
    } else {
      // The process data of 130 drives is split after (nearly) every frame;
      // the first run after a resume asks every slave on this thread.
      EXPECT_GE(lanes.chain.split_runs(), splits + 10) << "round " << round;
    }
    splits = lanes.chain.split_runs();
  }
  EXPECT_FALSE(lanes.chain.split_paused());
  ASSERT_EQ(lanes.frames.size(), ref.frames.size());
  for (std::size_t k = 0; k < lanes.frames.size(); ++k) ASSERT_EQ(lanes.frames[k], ref.frames[k]) << "frame " << k;
  for (std::size_t i = 0; i < kDrives; ++i) {
    const esc::Esc& x = lanes.chain[i].esc();
    const esc::Esc& y = ref.chain[i].esc();
    EXPECT_EQ(std::memcmp(x.memory(), y.memory(), x.memory_size()), 0) << "slave " << i;
    EXPECT_EQ(lanes.chain[i].status().application_cycles, ref.chain[i].status().application_cycles) << "slave " << i;
    EXPECT_EQ(lanes.chain[i].status().state, esc::AlState::Op) << "slave " << i;
  }
}

TEST(ChainLanes, ZeroThreadsIsRefused) {
  InProcess p;
  auto r = p.chain.set_firmware_threads(0);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error(), "firmware threads: at least 1");
  EXPECT_EQ(p.chain.firmware_threads(), 1u);
}

}  // namespace
}  // namespace ecat::test
