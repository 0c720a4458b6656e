// A chain whose segment lets frames pass the ESCs they do not address, and
// whose run_firmware asks only the slaves a frame entered, the pending ones
// and the ones whose time came (issue 16 item 5), against the same chain
// entering every ESC and asking every slave: the project's master takes
// both through scan, SII, mailbox/SDO, PreOp, SafeOp and Op and cycles
// process data; every frame that comes back and every ESC's memory at the
// end are the same.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

// Long enough for the segment to skip (esc::Segment::kSkipFrom) and the
// chain to keep wake times (slave::Chain::kTrackFrom).
constexpr std::size_t kDrives = slave::Chain::kTrackFrom + 2;

// An in-process master and chain that keeps every frame it returned.
struct Recorded {
  explicit Recorded(bool skipping) {
    p.chain.set_skipping(skipping);
    p.wire.set_processor([this](Bytes frame) {
      p.clock.advance(kWireTime);
      (void)p.chain.process_frame(frame, p.clock.now());
      frames.emplace_back(frame.begin(), frame.end());
    });
  }
  InProcess p;
  std::vector<std::vector<std::uint8_t>> frames;
};

TEST(ChainSkip, MasterBringUpAndCyclesGiveTheSameFramesAsTheFullPass) {
  Recorded fast(true);
  Recorded ref(false);
  for (Recorded* r : {&fast, &ref}) {
    r->p.add_default(kDrives);
    ASSERT_EQ(r->p.bring_up(), "");
    for (int c = 0; c < 200; ++c) ASSERT_TRUE(r->p.cycle_once(std::chrono::milliseconds(1))) << "cycle " << c;
  }
  ASSERT_EQ(fast.frames.size(), ref.frames.size());
  // The 200 cycle frames plus a bring-up of several hundred (the batched
  // scan, SII reads and mailbox traffic: 669 frames for 6 drives).
  EXPECT_GT(fast.frames.size(), 200u + 400u);
  for (std::size_t k = 0; k < fast.frames.size(); ++k) {
    ASSERT_EQ(fast.frames[k], ref.frames[k]) << "frame " << k;
  }
  for (std::size_t i = 0; i < kDrives; ++i) {
    const esc::Esc& x = fast.p.chain[i].esc();
    const esc::Esc& y = ref.p.chain[i].esc();
    ASSERT_EQ(x.memory_size(), y.memory_size());
    EXPECT_EQ(std::memcmp(x.memory(), y.memory(), x.memory_size()), 0) << "slave " << i;
    EXPECT_EQ(x.last_time(), y.last_time()) << "slave " << i;
    EXPECT_EQ(x.next_timer(), y.next_timer()) << "slave " << i;
    EXPECT_EQ(fast.p.chain[i].status().state, ref.p.chain[i].status().state) << "slave " << i;
  }
}

// The same on a tree (issue 30 item 2, esc/segment_route.cpp): drive 0 a
// junction of four ports with a branch of two drives on port 3, then drive
// 3 on its port 1 with one more on port 2 (entered last) and the rest in a
// line: a frame's order through the units is not the slaves' order.
TEST(ChainSkip, TreeBringUpAndCyclesGiveTheSameFramesAsThePortWalk) {
  auto device = esi::load_default_device();
  ASSERT_TRUE(device) << device.error().to_string();
  device->esc.physics = "YYYY";
  Recorded fast(true);
  Recorded ref(false);
  for (Recorded* r : {&fast, &ref}) {
    slave::SlaveOptions o;
    ASSERT_TRUE(r->p.chain.add(*device, o));
    ASSERT_TRUE(r->p.chain.attach(*device, o, 0, 3));
    ASSERT_TRUE(r->p.chain.attach(*device, o, 1, esc::kDownstreamPort));
    ASSERT_TRUE(r->p.chain.attach(*device, o, 0, esc::kDownstreamPort));
    ASSERT_TRUE(r->p.chain.attach(*device, o, 3, 2));
    ASSERT_TRUE(r->p.chain.attach(*device, o, 3, esc::kDownstreamPort));
    for (std::size_t k = 6; k < kDrives; ++k) ASSERT_TRUE(r->p.chain.attach(*device, o, k - 1, esc::kDownstreamPort));
    ASSERT_FALSE(r->p.chain.segment().is_line());
    ASSERT_EQ(r->p.bring_up(), "");
    for (int c = 0; c < 200; ++c) ASSERT_TRUE(r->p.cycle_once(std::chrono::milliseconds(1))) << "cycle " << c;
  }
  ASSERT_EQ(fast.frames.size(), ref.frames.size());
  EXPECT_GT(fast.frames.size(), 200u + 400u);
  for (std::size_t k = 0; k < fast.frames.size(); ++k) {
    ASSERT_EQ(fast.frames[k], ref.frames[k]) << "frame " << k;
  }
  for (std::size_t i = 0; i < kDrives; ++i) {
    const esc::Esc& x = fast.p.chain[i].esc();
    const esc::Esc& y = ref.p.chain[i].esc();
    EXPECT_EQ(std::memcmp(x.memory(), y.memory(), x.memory_size()), 0) << "slave " << i;
    EXPECT_EQ(x.last_time(), y.last_time()) << "slave " << i;
    EXPECT_EQ(x.next_timer(), y.next_timer()) << "slave " << i;
    EXPECT_EQ(fast.p.chain[i].status().state, ref.p.chain[i].status().state) << "slave " << i;
  }
}

// Each slave's ESC memory starts 64 x (position mod 8) bytes into its page
// (esc::EscConfig::memory_colour): neighbours never have the same register
// at the same address modulo 4 KiB.
TEST(ChainSkip, NeighbouringSlavesGetDifferentMemoryColours) {
  InProcess p;
  p.add_default(10);
  for (std::size_t i = 0; i < 10; ++i) {
    const auto at = reinterpret_cast<std::uintptr_t>(p.chain[i].esc().memory());
    EXPECT_EQ(at % 4096, 64u * (i % 8)) << "slave " << i;
  }
}

}  // namespace
}  // namespace ecat::test
