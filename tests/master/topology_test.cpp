// Topology and DC propagation delays of trees and lines (master/topology.hpp,
// master/dc_delay.hpp): first the pure computation on register values derived
// by hand from the ESC datasheet's forwarding order, then the master scanning
// a FakeTree (fake_tree.hpp) and writing 0x0928.
#include <gtest/gtest.h>

#include <optional>
#include <vector>

#include "fake_tree.hpp"
#include "master/dc_delay.hpp"
#include "master/master.hpp"
#include "master/topology.hpp"
#include "transport/in_memory_transport.hpp"

namespace ecat::master::test {
namespace {

// DL status 0x0110 by hand (esc-registers.md §4.7): bits 0,1 PDI operational
// and watchdog OK; 4+n link; 8+2n loop closed; 9+2n communication.
constexpr std::uint16_t kDlPorts012 = 0x6A73;   // coupler: ports 0,1,2 (port 3 absent, closed)
constexpr std::uint16_t kDlPorts0123 = 0xAAF3;  // junction: all four ports
constexpr std::uint16_t kDlPorts01 = 0x5A33;    // drive in a line: in on 0, out on 1
constexpr std::uint16_t kDlPort0 = 0x5613;      // end of a branch: port 0 only

TEST(Topology, ActivePortsFromDlStatus) {
  EXPECT_EQ(active_ports_from_dl_status(kDlPorts012), 0x07);
  EXPECT_EQ(active_ports_from_dl_status(kDlPorts0123), 0x0F);
  EXPECT_EQ(active_ports_from_dl_status(kDlPorts01), 0x03);
  EXPECT_EQ(active_ports_from_dl_status(kDlPort0), 0x01);
  // Communication without an open loop is not active, nor an open loop without communication.
  EXPECT_EQ(active_ports_from_dl_status(0x0300), 0x00);
  EXPECT_EQ(active_ports_from_dl_status(0x0000), 0x00);
  EXPECT_EQ(active_ports_from_dl_status(0x8000), 0x08);
  EXPECT_EQ(FakeTree::dl_status(0x07), kDlPorts012);
  EXPECT_EQ(FakeTree::dl_status(0x0F), kDlPorts0123);
  EXPECT_EQ(FakeTree::dl_status(0x03), kDlPorts01);
  EXPECT_EQ(FakeTree::dl_status(0x01), kDlPort0);
}

TEST(Topology, PortOrderIsZeroThreeOneTwo) {
  EXPECT_EQ(next_active_port(0x0F, 0), 3u);
  EXPECT_EQ(next_active_port(0x0F, 3), 1u);
  EXPECT_EQ(next_active_port(0x0F, 1), 2u);
  EXPECT_EQ(next_active_port(0x0F, 2), 0u);
  EXPECT_EQ(previous_active_port(0x0F, 0), 2u);
  EXPECT_EQ(previous_active_port(0x0F, 1), 3u);
  EXPECT_EQ(previous_active_port(0x0F, 3), 0u);
  EXPECT_EQ(next_active_port(0x07, 0), 1u);      // port 3 absent: skipped
  EXPECT_EQ(previous_active_port(0x07, 1), 0u);
  EXPECT_EQ(next_active_port(0x05, 0), 2u);
  EXPECT_EQ(previous_active_port(0x01, 0), 0u);  // only port: itself
  EXPECT_EQ(active_port_count(0x0B), 3u);
}

TEST(Topology, EntryPortIsTheFirstLatched) {
  EXPECT_EQ(entry_port(0x03, std::nullopt), 0u);
  EXPECT_EQ(entry_port(0x0A, std::nullopt), 3u);  // 3 comes before 1 in processing order
  EXPECT_EQ(entry_port(0x03, PortTimes{500, 100, 0, 0}), 1u);
  EXPECT_EQ(entry_port(0x03, PortTimes{100, 500, 0, 0}), 0u);
  // Across the 32-bit wrap: port 0 at 0xFFFFFF00 comes before port 1 at 0x100.
  EXPECT_EQ(entry_port(0x03, PortTimes{0xFFFFFF00u, 0x100, 0, 0}), 0u);
}

// The tree of the tests: coupler C (ports 0,1,2) with an E-bus terminal T on
// port 1 and a junction J on port 2; J (ports 0-3): drives A1-A2 on port 3,
// terminal E1 on port 1, drives B1-B2-B3 on port 2. Position order is the
// order the frame meets them: C T J A1 A2 E1 B1 B2 B3.
std::vector<TopologyInput> tree_dl_status() {
  return {{kDlPorts012, {}}, {kDlPort0, {}},   {kDlPorts0123, {}}, {kDlPorts01, {}}, {kDlPort0, {}},
          {kDlPort0, {}},    {kDlPorts01, {}}, {kDlPorts01, {}},   {kDlPort0, {}}};
}

TEST(Topology, TreeParentsAndPorts) {
  const auto t = compute_topology(tree_dl_status());
  ASSERT_EQ(t.size(), 9u);
  struct Want {
    std::optional<std::size_t> parent;
    unsigned port;
    unsigned count;
  };
  const Want want[9] = {{std::nullopt, 0, 3}, {0, 1, 1}, {0, 2, 4}, {2, 3, 2}, {3, 1, 1},
                        {2, 1, 1},            {2, 2, 2}, {6, 1, 2}, {7, 1, 1}};
  for (std::size_t i = 0; i < 9; ++i) {
    EXPECT_EQ(t[i].parent, want[i].parent) << i;
    EXPECT_EQ(t[i].parent_port, want[i].port) << i;
    EXPECT_EQ(t[i].port_count(), want[i].count) << i;
    EXPECT_EQ(t[i].entry_port, 0u) << i;
    EXPECT_EQ(t[i].open_end_ports, 0u) << i;  // every port has its slave
  }
}

TEST(Topology, LineAndRingEnd) {
  // A line of four: each on the previous one's port 1.
  std::vector<TopologyInput> line{{kDlPorts01, {}}, {kDlPorts01, {}}, {kDlPorts01, {}}, {kDlPort0, {}}};
  auto t = compute_topology(line);
  for (std::size_t i = 1; i < 4; ++i) {
    EXPECT_EQ(t[i].parent, std::optional<std::size_t>(i - 1));
    EXPECT_EQ(t[i].parent_port, 1u);
  }
  // Closed to a ring: the last slave's port 1 goes back to the master's second port.
  line[3].dl_status = kDlPorts01;
  t = compute_topology(line);
  EXPECT_EQ(t[3].open_end_ports, 0x02);
  EXPECT_EQ(t[2].open_end_ports, 0x00);
  // A slave whose DL status shows no port at all counts as having port 0.
  std::vector<TopologyInput> none{{0x0000, {}}};
  EXPECT_EQ(compute_topology(none).at(0).active_ports, 0x01);
}

// Port receive times of the tree (global ns, frame at C at t = 0), derived by
// hand with forward_ns = 200 per hop inside an ESC and these cables (one way):
// T 20, J 50, A1 100, A2 30, E1 20, B1 60, B2 40, B3 80.
//   C: port 0 at 0; out on 1 at 200, T at 220, T back out at 420, C port 1 at 440;
//      out on 2 at 640, J at 690 ... J back out at 3950, C port 2 at 4000.
//   J: port 0 690; out on 3 at 890, A1 at 990; A1 out on 1 at 1190, A2 at 1220,
//      A2 back at 1420, A1 port 1 at 1450; A1 out at 1650, J port 3 at 1750;
//      out on 1 at 1950, E1 at 1970, back 2170, J port 1 at 2190; out on 2 at
//      2390, B1 at 2450, B2 at 2690, B3 at 2970, B3 out 3170, B2 port 1 3250,
//      B2 out 3450, B1 port 1 3490, B1 out 3690, J port 2 at 3750.
// Each ESC latches its own local time: global + offset, mod 2^32 (C's wraps).
constexpr std::uint32_t kWrapOffset = 0xFFFFFFFFu - 999u;  // C: port 0 at 2^32 - 1000
std::vector<std::optional<PortTimes>> tree_port_times() {
  auto at = [](std::uint32_t offset, std::uint32_t p0, std::uint32_t p1, std::uint32_t p2, std::uint32_t p3) {
    // Ports without a link latch nothing useful: given 0 + offset here, and ignored.
    auto local = [&](std::uint32_t t) { return static_cast<std::uint32_t>(t + offset); };
    return std::optional<PortTimes>(PortTimes{local(p0), local(p1), local(p2), local(p3)});
  };
  return {at(kWrapOffset + 1, 0, 440, 4000, 0), at(5'000'000, 220, 0, 0, 0),  at(123, 690, 2190, 3750, 1750),
          at(7, 990, 1450, 0, 0),               at(0, 1220, 0, 0, 0),          at(42, 1970, 0, 0, 0),
          at(900'000, 2450, 3490, 0, 0),        at(1, 2690, 3250, 0, 0),       at(0xFFFF0000u, 2970, 0, 0, 0)};
}

// What each slave's delay must be: when the frame reached it, after C.
constexpr std::uint32_t kTreeDelays[9] = {0, 220, 690, 990, 1220, 1970, 2450, 2690, 2970};

TEST(DcDelay, TreeFromHandDerivedPortTimes) {
  auto in = tree_dl_status();
  const auto times = tree_port_times();
  for (std::size_t i = 0; i < in.size(); ++i) in[i].port_times = times[i];
  const auto topo = compute_topology(in);
  const auto d = compute_dc_delays(topo, times);
  ASSERT_EQ(d.size(), 9u);
  for (std::size_t i = 0; i < 9; ++i) EXPECT_EQ(d[i], std::optional<std::uint32_t>(kTreeDelays[i])) << i;
}

TEST(DcDelay, NonDcSlavesGetNoDelayAndCountAsCable) {
  auto in = tree_dl_status();
  auto times = tree_port_times();
  times[0].reset();  // C without DC: J becomes the reference
  times[6].reset();  // B1 without DC: B2 measured from J through B1
  const auto topo = compute_topology(in);
  const auto d = compute_dc_delays(topo, times);
  EXPECT_EQ(d[0], std::nullopt);
  EXPECT_EQ(d[1], std::optional<std::uint32_t>(0));  // T: no DC slave before it
  EXPECT_EQ(d[2], std::optional<std::uint32_t>(0));  // J: the reference
  EXPECT_EQ(d[3], std::optional<std::uint32_t>(990 - 690));
  EXPECT_EQ(d[6], std::nullopt);
  EXPECT_EQ(d[7], std::optional<std::uint32_t>(2690 - 690));  // exact: B1 forwards on two ports
  EXPECT_EQ(d[8], std::optional<std::uint32_t>(2970 - 690));
}

TEST(DcDelay, LineOfFour) {
  // Cables 50 ns, 200 ns per hop: slave k reached at 250 k; port 1 of slave k
  // latched at 250 k + 200 + round trip behind it.
  std::vector<TopologyInput> in{{kDlPorts01, {}}, {kDlPorts01, {}}, {kDlPorts01, {}}, {kDlPort0, {}}};
  std::vector<std::optional<PortTimes>> times{PortTimes{0, 1500, 0, 0}, PortTimes{250, 1250, 0, 0},
                                              PortTimes{500, 1000, 0, 0}, PortTimes{750, 0, 0, 0}};
  const auto d = compute_dc_delays(compute_topology(in), times);
  for (std::size_t k = 0; k < 4; ++k) EXPECT_EQ(d[k], std::optional<std::uint32_t>(250 * k)) << k;
}

TEST(DcDelay, SlaveEnteredOnPort1) {
  // Slave 1 is wired in on port 1 and out on port 2 (0 and 3 unused). With
  // 200 ns per hop and 50 ns cables: slave 1 reached at 250 on port 1, out on
  // port 2 at 450, slave 2 at 500 and back out at 700, slave 1 port 2 at 750,
  // out on port 1 at 950, slave 0 port 1 at 1000. Unused ports hold garbage.
  constexpr std::uint32_t kJunk = 0xDEADBEEF;
  const std::uint16_t dl_ports12 = FakeTree::dl_status(0x06);
  std::vector<std::optional<PortTimes>> times{PortTimes{0, 1000, kJunk, kJunk}, PortTimes{kJunk, 250, 750, 1},
                                              PortTimes{500, kJunk, kJunk, kJunk}};
  std::vector<TopologyInput> in{{kDlPorts01, times[0]}, {dl_ports12, times[1]}, {kDlPort0, times[2]}};
  const auto t = compute_topology(in);
  EXPECT_EQ(t[1].entry_port, 1u);
  EXPECT_EQ(t[2].parent, std::optional<std::size_t>(1));
  EXPECT_EQ(t[2].parent_port, 2u);  // after entry port 1 comes port 2
  const auto d = compute_dc_delays(t, times);
  EXPECT_EQ(d[1], std::optional<std::uint32_t>(250));
  EXPECT_EQ(d[2], std::optional<std::uint32_t>(500));
}

// The master scans a FakeTree and computes the same.
struct TreeRig {
  explicit TreeRig(std::vector<TreeNode> nodes)
      : tree(std::move(nodes)), bus([this](Bytes f) {
          tree.process(f, clock.now().count());
          clock.advance(std::chrono::microseconds(10));
        }),
        master(bus, clock) {}
  ManualClock clock;
  FakeTree tree;
  transport::InMemoryTransport bus;
  Master master;
};

std::vector<TreeNode> tree_nodes() {
  return {{std::nullopt, 0, 0x07, 0, kWrapOffset + 1}, {0, 1, 0x01, 20, 5'000'000}, {0, 2, 0x0F, 50, 123},
          {2, 3, 0x03, 100, 7},                       {3, 1, 0x01, 30, 0},         {2, 1, 0x01, 20, 42},
          {2, 2, 0x03, 60, 900'000},                  {6, 1, 0x03, 40, 1},         {7, 1, 0x01, 80, 0xFFFF0000u}};
}

TEST(DcDelay, MasterScansTheTreeAndWritesDelays) {
  TreeRig rig(tree_nodes());
  ASSERT_EQ(rig.master.scan().value_or(0), 9u);
  const std::optional<std::size_t> parents[9] = {std::nullopt, 0, 0, 2, 3, 2, 2, 6, 7};
  const unsigned ports[9] = {0, 1, 2, 3, 1, 1, 2, 1, 1};
  for (std::size_t i = 0; i < 9; ++i) {
    EXPECT_EQ(rig.master.slave(i).topology.parent, parents[i]) << i;
    EXPECT_EQ(rig.master.slave(i).topology.parent_port, ports[i]) << i;
  }
  auto n = rig.master.configure_dc(Nanoseconds{1'000'000'000});
  ASSERT_EQ(n.value_or(0), 9u);
  for (std::size_t i = 0; i < 9; ++i) {
    // The fake's own walk and the hand-derived figures agree ...
    EXPECT_EQ(rig.tree.arrival(i) - rig.tree.arrival(0), kTreeDelays[i]) << i;
    // ... and the master wrote them to 0x0928.
    EXPECT_EQ(rig.master.slave(i).dc.delay_ns, kTreeDelays[i]) << i;
    EXPECT_EQ(load_le<std::uint32_t>(rig.tree.esc(i).mem.data() + reg::kDcSystemTimeDelay), kTreeDelays[i]) << i;
    EXPECT_EQ(rig.master.slave(i).topology.entry_port, 0u) << i;
  }
}

TEST(DcDelay, MasterOnALineWithUnevenCables) {
  TreeRig rig({{std::nullopt, 0, 0x03, 0, 0}, {0, 1, 0x03, 10, 1000}, {1, 1, 0x03, 500, 77}, {2, 1, 0x01, 2, 9}});
  ASSERT_EQ(rig.master.scan().value_or(0), 4u);
  ASSERT_EQ(rig.master.configure_dc(Nanoseconds{0}).value_or(0), 4u);
  // Slave 1 at 200 + 10, slave 2 at 210 + 200 + 500, slave 3 at 910 + 200 + 2.
  const std::uint32_t want[4] = {0, 210, 910, 1112};
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(rig.master.slave(i).dc.delay_ns, want[i]) << i;
}

}  // namespace
}  // namespace ecat::master::test
