// Time inside an ESC (EscConfig::processing_delay / forwarding_delay,
// docs/esc.md "Forwarding delays inside an ESC"): a frame leaves the
// processing direction (port 0 -> unit -> next open port) after the
// processing delay and the forwarding direction (port 1..3 -> next open port)
// after the forwarding delay; the receive times 0x0900-0x090F latch the
// arrivals at the ports. Exact times in ns (DC clocks at 0 ppm from 0).
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "esc_fixture.hpp"

namespace ecat::esc::test {
namespace {

constexpr Nanoseconds kP{300}, kF{200}, kHop = Segment::kDefaultHopDelay;  // hop 1000

EscConfig delayed() {
  EscConfig c = make_config();
  c.processing_delay = kP;
  c.forwarding_delay = kF;
  return c;
}

std::uint32_t u32(Esc& e, std::uint16_t a) {
  return e.register_u16(a) | (std::uint32_t{e.register_u16(static_cast<std::uint16_t>(a + 2))} << 16);
}
std::array<std::uint32_t, 4> receive_times(Esc& e) {
  return {u32(e, reg::kDcBase), u32(e, reg::kDcBase + 4), u32(e, reg::kDcBase + 8), u32(e, reg::kDcBase + 12)};
}

Data latch_frame() {
  Segment scratch;  // no slaves: only finishes the frame
  TestFrame f;
  f.add(Command::Bwr, device_address(0, reg::kDcBase), 4);
  f.send(scratch);
  return Data(f.frame().begin(), f.frame().end());
}

// A line of three: out through each unit (P) and a cable, back through each
// port 1 -> port 0 (F) and a cable; the last one turns the frame round
// through its unit and closed ports (P).
TEST(EscInnerDelay, LineTimesAddProcessingOutAndForwardingBack) {
  Line line(3, delayed());
  EXPECT_TRUE(line.segment.is_line());  // one time inside for all: the line path adds it
  Data f = latch_frame();
  const Delivery d = line.segment.send(f, 0ns);
  ASSERT_TRUE(d.returned());
  const std::int64_t p = kP.count(), fw = kF.count(), h = kHop.count();
  const std::int64_t at1 = p + h;                // slave 1's port 0
  const std::int64_t at2 = at1 + p + h;          // slave 2's port 0
  const std::int64_t back1 = at2 + p + h;        // slave 1's port 1 (slave 2 turned it round)
  const std::int64_t back0 = back1 + fw + h;     // slave 0's port 1
  const std::int64_t at_master = back0 + fw;     // the master's cable takes 0
  using T = std::array<std::uint32_t, 4>;
  EXPECT_EQ(receive_times(line[0]), (T{0, static_cast<std::uint32_t>(back0), 0, 0}));
  EXPECT_EQ(receive_times(line[1]), (T{static_cast<std::uint32_t>(at1), static_cast<std::uint32_t>(back1), 0, 0}));
  EXPECT_EQ(receive_times(line[2]), (T{static_cast<std::uint32_t>(at2), 0, 0, 0}));
  EXPECT_EQ(d.at.count(), at_master);
  EXPECT_EQ(at_master, 5300);  // 3 P + 2 F + 4 hops, written out
}

// The same line as a port walk: cabled with an explicit cable delay
// (Segment::add with a parent), which leaves the line path.
struct WalkedLine {
  explicit WalkedLine(std::size_t n, EscConfig cfg) {
    for (std::size_t i = 0; i < n; ++i) {
      escs.push_back(std::make_unique<Esc>(cfg, clock));
      if (i == 0) {
        segment.add(*escs.back());
      } else {
        segment.add(*escs.back(), i - 1, kDownstreamPort, kUpstreamPort, kHop);
      }
    }
  }
  ManualClock clock;
  std::vector<std::unique_ptr<Esc>> escs;
  Segment segment;
};

// A line of one ESC type keeps the line path (and its skipping) with the
// times inside: every frame comes back with the same bytes at the same
// time as on the port walk, and every ESC - also the ones a frame passed
// by - ends with the same memory (receive times 0x0900-0x090F, the DC
// times a read of 0x0910 returns).
TEST(EscInnerDelay, ALineOfOneTypeGivesThePortWalksFramesAndTimes) {
  constexpr std::size_t kN = 5;
  Line fast(kN, delayed());
  WalkedLine walked(kN, delayed());
  ASSERT_TRUE(fast.segment.is_line());
  ASSERT_FALSE(walked.segment.is_line());
  struct Step {
    Command c;
    std::uint32_t address;
    std::uint16_t length;
  };
  const std::vector<Step> steps = {
      {Command::Bwr, device_address(0, reg::kDcBase), 4},                          // latch all receive times
      {Command::Aprd, device_address(auto_increment_adp(3), reg::kAlStatus), 2},   // only slave 3: the rest passed by
      {Command::Aprd, device_address(auto_increment_adp(1), reg::kDcBase), 16},    // slave 1's receive times
      {Command::Aprd, device_address(auto_increment_adp(4), reg::kDcBase + 0x10), 8},  // slave 4's system time
      {Command::Bwr, device_address(0, reg::kDcBase), 4},                          // latch again, later
      {Command::Aprd, device_address(auto_increment_adp(2), reg::kDcBase), 16},
  };
  Nanoseconds t{0};
  for (std::size_t k = 0; k < steps.size(); ++k) {
    t += 50'000ns;
    TestFrame a;
    TestFrame b;
    a.add(steps[k].c, steps[k].address, steps[k].length);
    b.add(steps[k].c, steps[k].address, steps[k].length);
    fast.clock.set(t);
    walked.clock.set(t);
    a.send(fast.segment, t);
    b.send(walked.segment, t);
    EXPECT_EQ(a.data(0), b.data(0)) << "step " << k;
    EXPECT_EQ(a.wkc(0), b.wkc(0)) << "step " << k;
  }
  // The times of the last frame: out P + hop per slave, back F + hop.
  Data f = latch_frame();
  const Delivery df = fast.segment.send(f, t + 50'000ns);
  Data g = latch_frame();
  const Delivery dw = walked.segment.send(g, t + 50'000ns);
  EXPECT_EQ(df.at, dw.at);
  EXPECT_EQ(df.at - (t + 50'000ns), kN * kP + (kN - 1) * kF + 2 * (kN - 1) * kHop);
  // The latest time each ESC saw the frame, as a passed-by ESC takes it
  // from the line's pass record (LinePass::latest), is the port walk's
  // port-1 arrival (the turning ESC: its port-0 arrival).
  LinePass pass;
  pass.start = t + 50'000ns;
  pass.out = kP + kHop;
  pass.back = kF + kHop;
  pass.reached = static_cast<std::uint32_t>(kN);
  pass.returned = true;
  for (std::size_t i = 0; i < kN; ++i) {
    const auto times = receive_times(*walked.escs[i]);
    const auto port = i + 1 < kN ? 1 : 0;
    const auto latest = static_cast<std::uint32_t>(pass.latest(static_cast<std::uint32_t>(i)).count());
    EXPECT_EQ(latest, times[port]) << "slave " << i;
    EXPECT_EQ(static_cast<std::uint32_t>(pass.at(static_cast<std::uint32_t>(i)).count()), times[0]) << "slave " << i;
  }
  for (std::size_t i = 0; i < kN; ++i) {
    ASSERT_EQ(fast[i].memory_size(), walked.escs[i]->memory_size());
    EXPECT_TRUE(std::equal(fast[i].memory(), fast[i].memory() + fast[i].memory_size(), walked.escs[i]->memory()))
        << "slave " << i;
    EXPECT_EQ(fast[i].last_time(), walked.escs[i]->last_time()) << "slave " << i;
  }
}

// ESCs that differ in their times inside take the port walk.
TEST(EscInnerDelay, ALineOfMixedTypesTakesThePortWalk) {
  Line line(2, delayed());
  EscConfig other = delayed();
  other.forwarding_delay = kF + 10ns;
  line.escs.push_back(std::make_unique<Esc>(other, line.clock));
  line.segment.add(*line.escs.back());
  EXPECT_FALSE(line.segment.is_line());
}

// Zero delays keep the line loop and the times of the cables alone.
TEST(EscInnerDelay, ZeroDelaysKeepTheLine) {
  Line line(3);
  EXPECT_TRUE(line.segment.is_line());
  Data f = latch_frame();
  EXPECT_EQ(line.segment.send(f, 0ns).at, 4 * kHop);
}

// The backward frame of a cut ring enters the far slave at port 1, is
// forwarded (F) to its closed port 0 and through its unit (P), then out of
// port 1 again: port 1 latched at arrival, port 0 (the unit) F later, back
// at the master F + P after it entered.
TEST(EscInnerDelay, BackwardFrameThroughAClosedPortZeroTakesBoth) {
  Line line(3, delayed());
  line.segment.connect_master(1, 2, kDownstreamPort);
  ASSERT_TRUE(line.segment.set_link(1, 1, false));
  Data f = latch_frame();
  const Delivery d = line.segment.send(f, 5000ns, 1);
  ASSERT_TRUE(d.returned());
  EXPECT_EQ(d.master_port, 1u);
  EXPECT_EQ(d.at, 5000ns + kF + kP);
  using T = std::array<std::uint32_t, 4>;
  EXPECT_EQ(receive_times(line[2]), (T{5000 + 200, 5000, 0, 0}));
  EXPECT_EQ(u32(line[2], reg::kDcBase + 0x18), 5000u + 200u);  // 0x0918: at the processing unit
}

}  // namespace
}  // namespace ecat::esc::test
