// Ports 0-3 of one ESC and of ESCs wired into trees and rings (issue 16):
// port descriptor 0x0007, DL status 0x0110 per port, loop control 0x0101
// (Auto, Auto-close, open, closed), lost-link counters 0x0310-0x0313, the
// processing order 0 -> PU -> 3 -> 1 -> 2 -> 0 (Section I §3.2 Table 9),
// receive-time latches 0x0900-0x090F per port and cable redundancy.
// Exact register values; simulated time (hop delay 1 µs, DC clocks at 0 ppm
// from local time 0, so local time = true time in ns).
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "dc_fixture.hpp"
#include "esc_fixture.hpp"

namespace ecat::esc::test {
namespace {

constexpr std::uint8_t kCouplerPorts = 0x3B;   // port 0 MII, 1 E-bus, 2 MII, 3 none
constexpr std::uint8_t kJunctionPorts = 0xFF;  // four MII ports

EscConfig config_with_ports(std::uint8_t descriptor) {
  EscConfig c = make_config();
  c.port_descriptor = descriptor;
  return c;
}

std::uint16_t dl_status(Esc& e) { return e.register_u16(reg::kDlStatus); }
std::uint8_t lost_link(Esc& e, unsigned port) { return e.memory()[reg::kLostLinkCounter + port]; }

// A set of ESCs that stays put while a Segment points at them.
struct Net {
  Esc& make(std::uint8_t descriptor = 0) {
    escs.push_back(std::make_unique<Esc>(descriptor ? config_with_ports(descriptor) : make_config(), clock));
    return *escs.back();
  }
  ManualClock clock;
  std::vector<std::unique_ptr<Esc>> escs;
  Segment segment;
};

// The 16 receive-time bytes 0x0900-0x090F of `station` as four u32.
std::array<std::uint32_t, 4> receive_times(Segment& s, std::uint16_t station) {
  const Data d = transact(s, Command::Fprd, fp(station, reg::kDcBase), 16).data;
  return {load_le<std::uint32_t>(d.data()), load_le<std::uint32_t>(d.data() + 4),
          load_le<std::uint32_t>(d.data() + 8), load_le<std::uint32_t>(d.data() + 12)};
}

// Station addresses by auto-increment position: the order in which the
// frame reaches the processing units.
void assign_by_position(Segment& s, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) {
    EXPECT_EQ(transact(s, Command::Apwr, ap(static_cast<std::uint16_t>(i), reg::kConfiguredStationAddress),
                       le16(static_cast<std::uint16_t>(0x1001 + i)))
                  .wkc,
              1);
  }
}

std::uint16_t station_of(Esc& e) { return e.register_u16(reg::kConfiguredStationAddress); }

TEST(EscPorts, PortDescriptorPerDevice) {
  ManualClock clock;
  Esc line_esc(make_config(), clock);
  Esc coupler(config_with_ports(kCouplerPorts), clock);
  Esc junction(config_with_ports(kJunctionPorts), clock);
  EXPECT_EQ(line_esc.memory()[reg::kPortDescriptor], 0x0F);
  EXPECT_EQ(coupler.memory()[reg::kPortDescriptor], 0x3B);
  EXPECT_EQ(junction.memory()[reg::kPortDescriptor], 0xFF);
  EXPECT_TRUE(coupler.port_present(2));
  EXPECT_FALSE(coupler.port_present(3));
  coupler.set_link(3, true);  // no port 3: no link, stays closed
  EXPECT_FALSE(coupler.link(3));
  // DL status: no link anywhere, every loop closed (bits 8, 10, 12, 14),
  // EEPROM loaded (bit 0).
  EXPECT_EQ(dl_status(coupler), 0x5501);
}

TEST(EscPorts, DlStatusOfALine) {
  Line line(2);
  // First ESC: links 0, 1 (bits 4, 5); ports 2, 3 closed (12, 14); communication 0, 1 (9, 11).
  EXPECT_EQ(dl_status(line[0]), 0x5A31);
  // Last ESC: link 0 (4); ports 1, 2, 3 closed (10, 12, 14); communication 0 (9).
  EXPECT_EQ(dl_status(line[1]), 0x5611);
  EXPECT_EQ(transact(line.segment, Command::Aprd, ap(1, reg::kDlStatus), 2).data, le16(0x5611));
}

// One junction with a single ESC on each of ports 3, 1 and 2: the processing
// units see the frame in the order junction, port 3, port 1, port 2.
TEST(EscPorts, ProcessingOrderOfAFourPortEsc) {
  Net n;
  const std::size_t j = n.segment.add(n.make(kJunctionPorts));
  const std::size_t on1 = n.segment.add(n.make(), j, 1);
  const std::size_t on2 = n.segment.add(n.make(), j, 2);
  const std::size_t on3 = n.segment.add(n.make(), j, 3);
  EXPECT_FALSE(n.segment.is_line());
  assign_by_position(n.segment, 4);
  EXPECT_EQ(station_of(n.segment[j]), 0x1001);
  EXPECT_EQ(station_of(n.segment[on3]), 0x1002);
  EXPECT_EQ(station_of(n.segment[on1]), 0x1003);
  EXPECT_EQ(station_of(n.segment[on2]), 0x1004);
  // All four ports of the junction linked and open, communication on each.
  EXPECT_EQ(dl_status(n.segment[j]), 0xAAF1);
  TestFrame f;
  f.add(Command::Brd, device_address(0, reg::kType), 1);
  const std::size_t aprd = f.add(Command::Aprd, ap(3, reg::kConfiguredStationAddress), 2);
  ASSERT_TRUE(f.send(n.segment));
  EXPECT_EQ(f.wkc(0), 4);
  EXPECT_EQ(f.data(aprd), le16(0x1004));  // position 3 = the ESC on port 2
  EXPECT_EQ(f.frame()[kMacSize] & kSourceMacProcessedBit, kSourceMacProcessedBit);
}

// A line carried by the port walk gives the same bytes and times as the
// line path.
TEST(EscPorts, PortWalkEqualsLinePathOnALine) {
  Net a, b;
  for (int i = 0; i < 3; ++i) a.segment.add(a.make());
  b.segment.add(b.make());
  b.segment.add(b.make(), 0, 1, 0, Segment::kDefaultHopDelay);
  b.segment.add(b.make(), 1, 1, 0, Segment::kDefaultHopDelay);
  EXPECT_TRUE(a.segment.is_line());
  EXPECT_FALSE(b.segment.is_line());
  assign_by_position(a.segment, 3);
  assign_by_position(b.segment, 3);
  transact(a.segment, Command::Bwr, device_address(0, reg::kDcBase), 4);
  transact(b.segment, Command::Bwr, device_address(0, reg::kDcBase), 4);
  for (std::uint16_t st = 0x1001; st <= 0x1003; ++st) {
    EXPECT_EQ(receive_times(a.segment, st), receive_times(b.segment, st)) << st;
  }
  EXPECT_EQ(receive_times(a.segment, 0x1001), (std::array<std::uint32_t, 4>{0, 4000, 0, 0}));
  EXPECT_EQ(receive_times(a.segment, 0x1002), (std::array<std::uint32_t, 4>{1000, 3000, 0, 0}));
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(dl_status(a.segment[i]), dl_status(b.segment[i]));
  Data fa(60, 0), fb;
  {
    TestFrame f;
    f.add(Command::Brd, device_address(0, reg::kDlStatus), 2);
    ASSERT_TRUE(f.send(a.segment));
    fa.assign(f.frame().begin(), f.frame().end());
  }
  {
    TestFrame f;
    f.add(Command::Brd, device_address(0, reg::kDlStatus), 2);
    ASSERT_TRUE(f.send(b.segment));
    fb.assign(f.frame().begin(), f.frame().end());
  }
  EXPECT_EQ(fa, fb);
}

// The tree of issue 16: coupler (port 1 to an E-bus terminal, port 2 out)
// -> junction (port 3 to a branch of two drives, port 1 to a branch of one).
struct Tree : Net {
  Tree() {
    coupler = segment.add(make(kCouplerPorts));
    terminal = segment.add(make(), coupler, 1);
    junction = segment.add(make(kJunctionPorts), coupler, 2);
    a1 = segment.add(make(), junction, 3);
    a2 = segment.add(make(), a1, 1);
    b = segment.add(make(), junction, 1);
    assign_by_position(segment, 6);
  }
  std::size_t coupler, terminal, junction, a1, a2, b;
};

TEST(EscTopology, TreeProcessingOrderAndDlStatus) {
  Tree t;
  // coupler, terminal, junction, branch A (a1, a2), branch B.
  EXPECT_EQ(station_of(t.segment[t.coupler]), 0x1001);
  EXPECT_EQ(station_of(t.segment[t.terminal]), 0x1002);
  EXPECT_EQ(station_of(t.segment[t.junction]), 0x1003);
  EXPECT_EQ(station_of(t.segment[t.a1]), 0x1004);
  EXPECT_EQ(station_of(t.segment[t.a2]), 0x1005);
  EXPECT_EQ(station_of(t.segment[t.b]), 0x1006);
  // Coupler: links 0-2 (0x70), port 3 closed (bit 14), communication 0-2 (9, 11, 13).
  EXPECT_EQ(dl_status(t.segment[t.coupler]), 0x6A71);
  // Junction: links 0, 1, 3 (0xB0), port 2 closed (12), communication 0, 1, 3 (9, 11, 15).
  EXPECT_EQ(dl_status(t.segment[t.junction]), 0x9AB1);
}

// Receive times with a 1 µs cable: coupler PU 0, terminal 1000, back at the
// coupler's port 1 2000, junction 3000, a1 4000, a2 5000, back at a1's port 1
// 6000, junction port 3 7000, b 8000, junction port 1 9000, coupler port 2 10000.
TEST(EscTopology, TreeReceiveTimesPerPort) {
  Tree t;
  EXPECT_EQ(transact(t.segment, Command::Bwr, device_address(0, reg::kDcBase), 4).wkc, 6);
  using T = std::array<std::uint32_t, 4>;
  EXPECT_EQ(receive_times(t.segment, 0x1001), (T{0, 2000, 10000, 0}));
  EXPECT_EQ(receive_times(t.segment, 0x1002), (T{1000, 0, 0, 0}));
  EXPECT_EQ(receive_times(t.segment, 0x1003), (T{3000, 9000, 0, 7000}));
  EXPECT_EQ(receive_times(t.segment, 0x1004), (T{4000, 6000, 0, 0}));
  EXPECT_EQ(receive_times(t.segment, 0x1005), (T{5000, 0, 0, 0}));
  EXPECT_EQ(receive_times(t.segment, 0x1006), (T{8000, 0, 0, 0}));
}

TEST(EscTopology, TreeFrameReturnsAfterTheLastPort) {
  Tree t;
  Segment scratch;  // no slaves: only finishes the frame
  Data frame = [&] {
    TestFrame f;
    f.add(Command::Brd, device_address(0, reg::kType), 1);
    f.send(scratch);
    return Data(f.frame().begin(), f.frame().end());
  }();
  const Delivery d = t.segment.send(frame, Nanoseconds{0});
  ASSERT_TRUE(d.returned());
  EXPECT_EQ(d.master_port, 0u);
  EXPECT_EQ(d.at, Nanoseconds{10000});
  EXPECT_EQ(d.processed, 6u);
}

// Link down/up on a branch port: both ends lose the link, DL status shows
// it, the junction's port 3 closes (Auto) so branch A drops out and branch B
// stays; the lost-link counters count once per end; AL status untouched.
TEST(EscTopology, BranchLinkCutAndRestore) {
  Tree t;
  Esc& j = t.segment[t.junction];
  Esc& a1 = t.segment[t.a1];
  transact(t.segment, Command::Brd, device_address(0, reg::kDlStatus), 2);  // acknowledge 0x0210 bit 2
  EXPECT_EQ(j.register_u16(reg::kEcatEventRequest) & bits::kEcatEventDlStatus, 0);
  ASSERT_TRUE(t.segment.set_link(t.junction, 3, false));
  EXPECT_FALSE(t.segment.link_up(t.a1, 0));
  // Junction: links 0, 1; ports 2, 3 closed; communication 0, 1.
  EXPECT_EQ(dl_status(j), 0x5A31);
  // a1: link 1 only; ports 0, 2, 3 closed; communication 1.
  EXPECT_EQ(dl_status(a1), 0x5921);
  EXPECT_EQ(lost_link(j, 3), 1);
  EXPECT_EQ(lost_link(j, 0), 0);
  EXPECT_EQ(lost_link(a1, 0), 1);
  EXPECT_EQ(j.register_u16(reg::kEcatEventRequest) & bits::kEcatEventDlStatus, bits::kEcatEventDlStatus);
  EXPECT_EQ(j.register_u16(reg::kAlStatus), 0x0001);
  // Branch A is gone, the rest still answers in order.
  EXPECT_EQ(transact(t.segment, Command::Brd, device_address(0, reg::kType), 1).wkc, 4);
  EXPECT_EQ(transact(t.segment, Command::Aprd, ap(3, reg::kConfiguredStationAddress), 2).data, le16(0x1006));
  // The master reads the counters of the junction and clears them with a write.
  EXPECT_EQ(transact(t.segment, Command::Fprd, fp(0x1003, reg::kLostLinkCounter), 4).data, (Data{0, 0, 0, 1}));
  // Restored: Auto opens the port again; the counter keeps its count.
  ASSERT_TRUE(t.segment.set_link(t.junction, 3, true));
  EXPECT_EQ(dl_status(j), 0x9AB1);
  EXPECT_EQ(transact(t.segment, Command::Brd, device_address(0, reg::kType), 1).wkc, 6);
  EXPECT_EQ(lost_link(j, 3), 1);
  EXPECT_EQ(transact(t.segment, Command::Fpwr, fp(0x1003, reg::kLostLinkCounter), Data{0}).wkc, 1);
  EXPECT_EQ(lost_link(j, 3), 0);
  EXPECT_EQ(a1.register_u16(reg::kAlStatus), 0x0001);
}

// Loop control per port on the junction's port 3 (0x0101 bits 7:6).
TEST(EscTopology, LoopControlModes) {
  Tree t;
  Esc& j = t.segment[t.junction];
  auto set_loop_port3 = [&](std::uint8_t mode) {
    EXPECT_EQ(transact(t.segment, Command::Fpwr, fp(0x1003, reg::kDlControl + 1),
                       Data{static_cast<std::uint8_t>(mode << 6)})
                  .wkc,
              1);
  };
  auto wkc = [&] { return transact(t.segment, Command::Brd, device_address(0, reg::kType), 1).wkc; };
  // Closed: branch A is cut off with the link up; DL status shows link and closed loop.
  set_loop_port3(bits::kLoopClosed);
  EXPECT_EQ(wkc(), 4);
  EXPECT_EQ(dl_status(j), 0xDAB1);
  // Open: as Auto while the link is up.
  set_loop_port3(bits::kLoopOpen);
  EXPECT_EQ(wkc(), 6);
  // Open without a link: the frame is lost there.
  t.segment.set_link(t.junction, 3, false);
  EXPECT_EQ(lost_link(j, 3), 0);  // not counted in "open" mode
  TestFrame f;
  f.add(Command::Brd, device_address(0, reg::kType), 1);
  EXPECT_FALSE(f.send(t.segment));
  t.segment.set_link(t.junction, 3, true);
  // Auto-close: a link loss closes the port, and the link coming back does not open it.
  set_loop_port3(bits::kLoopAutoClose);
  EXPECT_EQ(wkc(), 6);
  t.segment.set_link(t.junction, 3, false);
  EXPECT_EQ(lost_link(j, 3), 1);
  t.segment.set_link(t.junction, 3, true);
  EXPECT_EQ(dl_status(j), 0xDAB1);  // "closed wait": link up, loop closed
  EXPECT_EQ(wkc(), 4);
  // Writing the loop configuration again opens it.
  set_loop_port3(bits::kLoopAutoClose);
  EXPECT_EQ(dl_status(j), 0x9AB1);
  EXPECT_EQ(wkc(), 6);
}

// A port 0 forced closed takes no frame in: the frame is lost.
TEST(EscTopology, ClosedPortZeroTakesNothingIn) {
  Line line(3);
  assign_stations(line);
  // The last slave closes its port 0; the frame that does it still leaves
  // through port 0 (every port closed, Section I §3.2 Figure 5).
  EXPECT_EQ(transact(line.segment, Command::Fpwr, fp(0x1003, reg::kDlControl + 1), Data{0x03}).wkc, 1);
  TestFrame f;
  f.add(Command::Brd, device_address(0, reg::kType), 1);
  EXPECT_FALSE(f.send(line.segment));
}

// A ring of four slaves with both ends on the master: 0 -> 1 -> 2 -> 3 -> master port 1.
struct Ring : Net {
  Ring() {
    for (int i = 0; i < 4; ++i) segment.add(make());
    segment.connect_master(1, 3, 1);
    assign_by_position(segment, 4);
  }
  Data brd_frame() {
    TestFrame f;
    f.add(Command::Brd, device_address(0, reg::kType), 1);
    f.add(Command::Aprd, ap(0, reg::kConfiguredStationAddress), 2);
    f.send(scratch);
    return Data(f.frame().begin(), f.frame().end());
  }
  Segment scratch;  // no slaves: only finishes frames
};

DatagramView first_datagram(Data& frame) { return (*parse_frame(frame))[0]; }

TEST(EscTopology, RingIntactForwardsEachDirection) {
  Ring r;
  EXPECT_FALSE(r.segment.is_line());
  Data out = r.brd_frame();
  Delivery d = r.segment.send(out, Nanoseconds{0}, 0);
  ASSERT_TRUE(d.returned());
  EXPECT_EQ(d.master_port, 1u);  // through all four, out at the far end
  EXPECT_EQ(d.processed, 4u);
  EXPECT_EQ(first_datagram(out).wkc(), 4);
  EXPECT_EQ((*parse_frame(out))[1].data()[0], 0x01);  // station 0x1001 at position 0
  // Sent on the redundant port, the frame travels backwards unprocessed.
  Data back = r.brd_frame();
  d = r.segment.send(back, Nanoseconds{0}, 1);
  ASSERT_TRUE(d.returned());
  EXPECT_EQ(d.master_port, 0u);
  EXPECT_EQ(d.processed, 0u);
  EXPECT_EQ(first_datagram(back).wkc(), 0);
  EXPECT_EQ(back[kMacSize] & kSourceMacProcessedBit, 0);
  EXPECT_EQ(d.at, Nanoseconds{3000});
}

// A cut between slaves 1 and 2: the frame from port 0 serves 0 and 1 and
// comes back on port 0; the frame from port 1 runs backwards to slave 2,
// whose closed port 0 turns it into its processing unit, then forward
// through 3 back to port 1. Every slave processed exactly once in total.
TEST(EscTopology, RingCutKeepsEverySlaveReachable) {
  Ring r;
  ASSERT_TRUE(r.segment.set_link(1, 1, false));
  Data a = r.brd_frame();
  Data b = r.brd_frame();
  const Delivery da = r.segment.send(a, Nanoseconds{0}, 0);
  const Delivery db = r.segment.send(b, Nanoseconds{0}, 1);
  ASSERT_TRUE(da.returned());
  ASSERT_TRUE(db.returned());
  EXPECT_EQ(da.master_port, 0u);
  EXPECT_EQ(db.master_port, 1u);
  EXPECT_EQ(da.processed, 2u);
  EXPECT_EQ(db.processed, 2u);
  EXPECT_EQ(first_datagram(a).wkc() + first_datagram(b).wkc(), 4);
  EXPECT_EQ(first_datagram(a).wkc(), 2);
  // Position 0 of frame b is slave 2 (station 0x1003), and it passed a closed port 0.
  EXPECT_EQ((*parse_frame(b))[1].data()[0], 0x03);
  EXPECT_TRUE(first_datagram(b).circulating());
  EXPECT_FALSE(first_datagram(a).circulating());
  EXPECT_EQ(lost_link(r.segment[1], 1), 1);
  EXPECT_EQ(lost_link(r.segment[2], 0), 1);
  // Slave 2: link on 1 only; loops 0, 2, 3 closed; communication 1.
  EXPECT_EQ(dl_status(r.segment[2]), 0x5921);
  // Restored: the whole ring answers from port 0 again.
  ASSERT_TRUE(r.segment.set_link(2, 0, true));
  Data c = r.brd_frame();
  EXPECT_EQ(r.segment.send(c, Nanoseconds{0}, 0).master_port, 1u);
  EXPECT_EQ(first_datagram(c).wkc(), 4);
}

// Receive times of a frame that enters a slave at port 1 before its
// processing unit (the backward frame of a cut ring): the 0x0900 write
// latches port 1's earlier arrival too.
TEST(EscTopology, RingCutReceiveTimesBeforeProcessing) {
  Ring r;
  r.segment.set_link(1, 1, false);
  Data b = [&] {
    TestFrame f;
    f.add(Command::Bwr, device_address(0, reg::kDcBase), 4);
    f.send(r.scratch);
    return Data(f.frame().begin(), f.frame().end());
  }();
  ASSERT_TRUE(r.segment.send(b, Nanoseconds{5000}, 1).returned());
  EXPECT_EQ(first_datagram(b).wkc(), 2);
  // Read back through the far end (the near end only reaches 0x1001/0x1002).
  auto times = [&](std::uint16_t station) {
    Data f = [&] {
      TestFrame t;
      t.add(Command::Fprd, fp(station, reg::kDcBase), 16);
      t.send(r.scratch);
      return Data(t.frame().begin(), t.frame().end());
    }();
    EXPECT_TRUE(r.segment.send(f, Nanoseconds{20000}, 1).returned());
    const auto d = (*parse_frame(f))[0].data();
    return std::array<std::uint32_t, 4>{load_le<std::uint32_t>(d.data()), load_le<std::uint32_t>(d.data() + 4),
                                        load_le<std::uint32_t>(d.data() + 8), load_le<std::uint32_t>(d.data() + 12)};
  };
  using T = std::array<std::uint32_t, 4>;
  // Sent at 5000: slave 3's port 1 at 5000 (from the master), its
  // processing unit at 7000 after the round through slave 2; slave 2's
  // port 1 at 6000 and its processing unit (via the closed port 0) at 6000.
  EXPECT_EQ(times(0x1004), (T{7000, 5000, 0, 0}));
  EXPECT_EQ(times(0x1003), (T{6000, 6000, 0, 0}));
}

}  // namespace
}  // namespace ecat::esc::test
