// Error counters 0x0300-0x0313 as silicon keeps them (Section I §14 Table 50,
// §14.1 Table 51, §14.2; Section II 0x0300-0x030E) with cables that corrupt
// frames (Segment::corrupt_link): the ESC behind the broken cable counts the
// error as its own, every later port a forwarded error, every later
// processing unit 0x030C; the frame comes back with a bad FCS. Exact
// register values, read over the wire as a master's diagnosis reads them.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "esc_fixture.hpp"

namespace ecat::esc::test {
namespace {

constexpr std::uint16_t kRam = 0x1000;
constexpr std::size_t kCounterBytes = 0x0314 - 0x0300;  // 0x0300-0x0313

// A frame with one BWR of 4 bytes at 0x1000.
Data bwr_frame(std::uint8_t value = 1) {
  Data buf(60);
  FrameBuilder b(buf);
  (void)b.append(Command::Bwr, 0, device_address(0, kRam), Data{value, 2, 3, 4});
  b.finish();
  return buf;
}

// The WKC of bwr_frame's one datagram (4 data bytes), as the frame came back.
std::uint16_t bwr_wkc(const Data& f) {
  constexpr std::size_t kBwrData = 4;
  return load_le<std::uint16_t>(f.data() + kEthernetHeaderSize + kFrameHeaderSize + kDatagramHeaderSize + kBwrData);
}

// 0x0300-0x0313 of one ESC, straight from its memory.
Data counters(Esc& e) {
  const std::uint8_t* m = e.memory();
  return Data(m + reg::kRxErrorCounter, m + reg::kRxErrorCounter + kCounterBytes);
}

// The same registers with an ordinary frame from the master (APRD), as
// SOEM's and TwinCAT's diagnosis read them.
Data counters_over_wire(Segment& s, std::uint16_t position) {
  return transact(s, Command::Aprd, ap(position, reg::kRxErrorCounter), static_cast<std::uint16_t>(kCounterBytes))
      .data;
}

// Builds the expected 20 bytes: invalid-frame / RX error per port, forwarded
// per port, processing unit, PDI, PDI code (2), lost link per port.
struct Expect {
  std::array<std::uint8_t, 4> invalid{};
  std::array<std::uint8_t, 4> rx{};
  std::array<std::uint8_t, 4> forwarded{};
  std::uint8_t unit = 0;
  Data bytes() const {
    Data d(kCounterBytes, 0);
    for (unsigned p = 0; p < 4; ++p) {
      d[2 * p] = invalid[p];
      d[2 * p + 1] = rx[p];
      d[8 + p] = forwarded[p];
    }
    d[0x0C] = unit;
    return d;
  }
};

TEST(EscErrorCounters, CrcErrorOnALineCableIsLocalised) {
  Line line(4);
  Segment& s = line.segment;
  // The cable between slave 1 (its port 1) and slave 2 (its port 0), 0-based 0|1.
  ASSERT_TRUE(s.corrupt_link(1, 0, 1));
  EXPECT_EQ(s.corruption_pending(0, 1), 1u);  // the same cable from its other end
  EXPECT_EQ(s.corruption_pending(1, 0), 1u);
  Data f = bwr_frame();
  const Delivery d = s.send(f, 0ns);
  EXPECT_EQ(d.outcome, Delivery::Outcome::Corrupted);  // back on the master port with a bad FCS
  EXPECT_EQ(d.master_port, 0u);
  EXPECT_EQ(d.processed, 1u);
  EXPECT_FALSE(d.returned());
  EXPECT_EQ(s.corruption_pending(1, 0), 0u);
  // Slave 0 processed the frame before the cable; the others discarded it.
  EXPECT_EQ(line[0].memory()[kRam], 1);
  for (std::size_t i = 1; i < 4; ++i) EXPECT_EQ(line[i].memory()[kRam], 0) << i;
  // Slave 1 found the error at port 0 (0x0300) and in its unit (0x030C);
  // 2 and 3 got it marked at port 0 (0x0308); on the way back 2, 1 and 0
  // see the marked frame at port 1 (0x0309); slave 3 loops it back inside.
  EXPECT_EQ(counters(line[0]), (Expect{{}, {}, {0, 1, 0, 0}, 0}.bytes()));
  EXPECT_EQ(counters(line[1]), (Expect{{1, 0, 0, 0}, {}, {0, 1, 0, 0}, 1}.bytes()));
  EXPECT_EQ(counters(line[2]), (Expect{{}, {}, {1, 1, 0, 0}, 1}.bytes()));
  EXPECT_EQ(counters(line[3]), (Expect{{}, {}, {1, 0, 0, 0}, 1}.bytes()));
  // The master reads the same over the repaired line (the next frames pass).
  for (std::uint16_t i = 0; i < 4; ++i) EXPECT_EQ(counters_over_wire(s, i), counters(line[i])) << i;
  EXPECT_EQ(s.frames_dropped(), 1u);
}

TEST(EscErrorCounters, PhysicalLayerErrorCountsTheRxErrorByteToo) {
  Line line(2);
  ASSERT_TRUE(line.segment.corrupt_link(0, 1, 1, Segment::CableFault::RxError));
  Data f = bwr_frame();
  EXPECT_EQ(line.segment.send(f, 0ns).outcome, Delivery::Outcome::Corrupted);
  // Section I §14 Table 50 note: an RX error at port 0 counts in 0x0300, 0x0301 and 0x030C.
  EXPECT_EQ(counters(line[1]), (Expect{{1, 0, 0, 0}, {1, 0, 0, 0}, {}, 1}.bytes()));
  EXPECT_EQ(counters(line[0]), (Expect{{}, {}, {0, 1, 0, 0}, 0}.bytes()));
}

TEST(EscErrorCounters, MasterCableErrorCountsAtTheFirstSlave) {
  Line line(2);
  ASSERT_TRUE(line.segment.corrupt_link(0, 0, 1));
  Data f = bwr_frame();
  EXPECT_EQ(line.segment.send(f, 0ns).outcome, Delivery::Outcome::Corrupted);
  EXPECT_EQ(counters(line[0]), (Expect{{1, 0, 0, 0}, {}, {0, 1, 0, 0}, 1}.bytes()));
  EXPECT_EQ(counters(line[1]), (Expect{{}, {}, {1, 0, 0, 0}, 1}.bytes()));
  EXPECT_EQ(line[0].memory()[kRam], 0);
}

TEST(EscErrorCounters, NFramesThenTheCableIsGoodAgain) {
  Line line(3);
  Segment& s = line.segment;
  ASSERT_TRUE(s.corrupt_link(2, 0, 3));
  for (int i = 0; i < 3; ++i) {
    Data f = bwr_frame(static_cast<std::uint8_t>(10 + i));
    EXPECT_EQ(s.send(f, Nanoseconds{i * 1000}).outcome, Delivery::Outcome::Corrupted) << i;
    EXPECT_EQ(s.corruption_pending(2, 0), static_cast<unsigned>(2 - i));
  }
  Data f = bwr_frame(20);
  const Delivery d = s.send(f, 5000ns);
  EXPECT_EQ(d.outcome, Delivery::Outcome::Returned);
  EXPECT_EQ(bwr_wkc(f), 3);  // every slave
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(line[i].memory()[kRam], 20);
  EXPECT_EQ(counters(line[0]), (Expect{{}, {}, {0, 3, 0, 0}, 0}.bytes()));
  EXPECT_EQ(counters(line[1]), (Expect{{}, {}, {0, 3, 0, 0}, 0}.bytes()));
  EXPECT_EQ(counters(line[2]), (Expect{{3, 0, 0, 0}, {}, {}, 3}.bytes()));
}

// A segment of one ESC takes its own short path (Segment::carry_one) only
// while its master cable is healthy and up: a fault or a lost link on that
// cable takes the frame through the port walk, and the short path comes back
// when the cable is good again.
TEST(EscErrorCounters, OneEscSegmentSeesItsMasterCableFaultsAndLinkLoss) {
  Line line(1);
  Segment& s = line.segment;
  ASSERT_TRUE(s.corrupt_link(0, 0, 2));
  for (std::uint8_t i = 0; i < 2; ++i) {
    Data f = bwr_frame(static_cast<std::uint8_t>(10 + i));
    EXPECT_EQ(s.send(f, Nanoseconds{i * 1000}).outcome, Delivery::Outcome::Corrupted) << int{i};
  }
  EXPECT_EQ(line[0].memory()[kRam], 0);
  EXPECT_EQ(counters(line[0]), (Expect{{2, 0, 0, 0}, {}, {}, 2}.bytes()));
  Data good = bwr_frame(20);
  EXPECT_EQ(s.send(good, 3000ns).outcome, Delivery::Outcome::Returned);
  EXPECT_EQ(bwr_wkc(good), 1);
  EXPECT_EQ(line[0].memory()[kRam], 20);

  ASSERT_TRUE(s.set_link(0, 0, false));
  Data lost = bwr_frame(30);
  EXPECT_EQ(s.send(lost, 4000ns).outcome, Delivery::Outcome::Lost);
  EXPECT_EQ(line[0].memory()[kRam], 20);
  ASSERT_TRUE(s.set_link(0, 0, true));
  Data back = bwr_frame(40);
  EXPECT_EQ(s.send(back, 5000ns).outcome, Delivery::Outcome::Returned);
  EXPECT_EQ(bwr_wkc(back), 1);
  EXPECT_EQ(line[0].memory()[kRam], 40);
}

TEST(EscErrorCounters, CountersSaturateAt0xFF) {
  Line line(2);
  ASSERT_TRUE(line.segment.corrupt_link(1, 0, 300, Segment::CableFault::RxError));
  for (int i = 0; i < 300; ++i) {
    Data f = bwr_frame();
    (void)line.segment.send(f, Nanoseconds{i * 1000});
  }
  EXPECT_EQ(counters(line[1]), (Expect{{0xFF, 0, 0, 0}, {0xFF, 0, 0, 0}, {}, 0xFF}.bytes()));
  EXPECT_EQ(counters(line[0]), (Expect{{}, {}, {0, 0xFF, 0, 0}, 0}.bytes()));
}

TEST(EscErrorCounters, RepairingTheCableStopsTheFault) {
  Line line(2);
  ASSERT_TRUE(line.segment.corrupt_link(0, 1, 5));
  ASSERT_TRUE(line.segment.corrupt_link(1, 0, 0));
  EXPECT_EQ(line.segment.corruption_pending(0, 1), 0u);
  Data f = bwr_frame();
  EXPECT_TRUE(line.segment.process_frame(f, 0ns));
  EXPECT_FALSE(line.segment.corrupt_link(1, 1, 1));  // nothing cabled there
  EXPECT_FALSE(line.segment.corrupt_link(7, 0, 1));
}

// Section II 0x0300-0x030C: a write to any of 0x0300-0x030B clears those
// twelve; 0x030C only by its own write; 0x0310-0x0313 stay.
TEST(EscErrorCounters, ClearingByWrites) {
  Line line(2);
  Segment& s = line.segment;
  ASSERT_TRUE(s.corrupt_link(1, 0, 2, Segment::CableFault::RxError));
  for (int i = 0; i < 2; ++i) {
    Data f = bwr_frame();
    (void)s.send(f, 0ns);
  }
  ASSERT_TRUE(s.set_link(0, 1, false));  // a lost link on both ends of the cable
  ASSERT_TRUE(s.set_link(0, 1, true));
  Expect e1{{2, 0, 0, 0}, {2, 0, 0, 0}, {}, 2};
  Data want = e1.bytes();
  want[0x10] = 1;  // lost link port 0
  EXPECT_EQ(counters(line[1]), want);
  EXPECT_EQ(transact(s, Command::Apwr, ap(1, reg::kForwardedRxErrorCounter + 3), Data{0x55}).wkc, 1);
  want = Expect{{}, {}, {}, 2}.bytes();
  want[0x10] = 1;
  EXPECT_EQ(counters(line[1]), want);
  EXPECT_EQ(transact(s, Command::Apwr, ap(1, reg::kProcessingUnitErrorCounter), Data{0}).wkc, 1);
  want[0x0C] = 0;
  EXPECT_EQ(counters(line[1]), want);
  EXPECT_EQ(transact(s, Command::Apwr, ap(1, reg::kLostLinkCounter + 2), Data{0}).wkc, 1);
  EXPECT_EQ(counters(line[1]), Data(kCounterBytes, 0));
}

// Section II 0x030D/0x030E: the PDI's error count and code; writing 0x030D
// clears both; the PDI side cannot clear them.
TEST(EscErrorCounters, PdiErrorCounterAndCode) {
  Line line(1);
  line[0].count_pdi_error(0x2A);
  line[0].count_pdi_error(0x15);
  EXPECT_EQ(transact(line.segment, Command::Aprd, ap(0, reg::kPdiErrorCounter), 2).data, (Data{2, 0x15}));
  const std::uint8_t zero = 0;
  line[0].write(reg::kPdiErrorCounter, std::span(&zero, 1));
  EXPECT_EQ(line[0].memory()[reg::kPdiErrorCounter], 2);
  EXPECT_EQ(transact(line.segment, Command::Apwr, ap(0, reg::kPdiErrorCounter), Data{0}).wkc, 1);
  EXPECT_EQ(line[0].memory()[reg::kPdiErrorCounter], 0);
  EXPECT_EQ(line[0].memory()[reg::kPdiErrorCode], 0);
}

// A tree (coupler C, junction J on C's port 1, A on J's port 3, B on J's
// port 2): a fault on the cable J:3-A:0 is A's own error; J counts the
// returning frame as forwarded at port 3 and again at port 2 when B sends it
// back, B at its port 0, C at its port 1.
TEST(EscErrorCounters, TreeBranchFaultCountsPerPort) {
  ManualClock clock;
  EscConfig coupler = make_config();
  coupler.port_descriptor = 0x3B;  // 0 MII, 1 E-bus, 2 MII, no 3
  EscConfig junction = make_config();
  junction.port_descriptor = 0xFF;
  Esc c(coupler, clock), j(junction, clock), a(make_config(), clock), b(make_config(), clock);
  Segment s;
  const std::size_t ci = s.add(c);
  const std::size_t ji = s.add(j, ci, 1);
  const std::size_t ai = s.add(a, ji, 3);
  const std::size_t bi = s.add(b, ji, 2);
  ASSERT_TRUE(s.corrupt_link(ji, 3, 1));
  EXPECT_EQ(s.corruption_pending(ai, 0), 1u);
  Data f = bwr_frame();
  const Delivery d = s.send(f, 0ns);
  EXPECT_EQ(d.outcome, Delivery::Outcome::Corrupted);
  EXPECT_EQ(d.processed, 2u);  // C and J before the cable
  EXPECT_EQ(counters(c), (Expect{{}, {}, {0, 1, 0, 0}, 0}.bytes()));
  EXPECT_EQ(counters(j), (Expect{{}, {}, {0, 0, 1, 1}, 0}.bytes()));
  EXPECT_EQ(counters(a), (Expect{{1, 0, 0, 0}, {}, {}, 1}.bytes()));
  EXPECT_EQ(counters(b), (Expect{{}, {}, {1, 0, 0, 0}, 1}.bytes()));
  EXPECT_EQ(c.memory()[kRam], 1);
  EXPECT_EQ(j.memory()[kRam], 1);
  EXPECT_EQ(a.memory()[kRam], 0);
  EXPECT_EQ(b.memory()[kRam], 0);
  (void)bi;
  // The next frame passes intact and reaches all four.
  Data g = bwr_frame(7);
  EXPECT_TRUE(s.process_frame(g, 1000ns));
  EXPECT_EQ(b.memory()[kRam], 7);
}

// A malformed frame from the master: the first processing unit rejects it
// (0x030C, not a port error); in a ring it is marked on the way to the
// second master port, and the frame changes no ESC.
TEST(EscErrorCounters, MalformedFrameInARing) {
  Line line(3);
  Segment& s = line.segment;
  s.connect_master(1, 2, 1);
  Data f = bwr_frame();
  f[16] = 0x20;  // unknown command
  const Delivery d = s.send(f, 0ns);
  EXPECT_EQ(d.outcome, Delivery::Outcome::Malformed);
  EXPECT_EQ(counters(line[0]), (Expect{{}, {}, {}, 1}.bytes()));
  EXPECT_EQ(counters(line[1]), (Expect{{}, {}, {1, 0, 0, 0}, 1}.bytes()));
  EXPECT_EQ(counters(line[2]), (Expect{{}, {}, {1, 0, 0, 0}, 1}.bytes()));
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(line[i].memory()[kRam], 0);
}

}  // namespace
}  // namespace ecat::esc::test
