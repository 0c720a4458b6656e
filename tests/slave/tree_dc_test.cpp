// The tree of issue 16 item 6 — coupler -> junction -> two branches of
// drives, and a drive behind the coupler — built from the shipped device
// files with an explicit delay per cable, scanned by the project's master:
// every slave's parent, parent port and entry port are the tree as built,
// and the DC delays configure_dc writes to 0x0928 (read back from each ESC)
// are the ones the cables and the ESCs' inner delays give. Then link down/up
// on a junction branch port: the DL status of silicon, AL states untouched.
#include <gtest/gtest.h>

#include <array>
#include <string>

#include "esc/registers.hpp"
#include "master/registers.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

using std::chrono::nanoseconds;

od::DeviceDescription load(const std::string& name) {
  auto d = esi::load_device_file(std::string(ECAT_SOURCE_DIR) + "/xml/devices/" + name);
  if (!d) throw std::runtime_error(d.error().to_string());
  return std::move(*d);
}

// Positions (auto-increment order = the order the frame meets the slaves:
// port 0 -> processing unit -> 3 -> 1 -> 2, Section I §3.2 Table 9):
//   0 C  coupler-3port     on the master (port 0)
//   1 J  junction-4port    on C port 1 (E-bus)         cable CJ
//   2 A1 generic-servo     on J port 3                  cable JA1
//   3 A2 generic-servo     on A1 port 1                 cable A1A2
//   4 B1 generic-servo     on J port 2                  cable JB1
//   5 B2 generic-servo     on B1 port 1                 cable B1B2
//   6 B3 generic-servo     on B2 port 1                 cable B2B3
//   7 D  generic-servo     on C port 2 (the coupler's RJ45 out) cable CD
// J's port 1 (E-bus out) stays free: closed in Auto.
// Cable delays, all different, so a term taken from the wrong cable shows:
constexpr nanoseconds kCJ{150}, kJA1{710}, kA1A2{520}, kJB1{930}, kB1B2{440}, kB2B3{370}, kCD{610};
// Time inside each ESC (EscConfig::processing_delay P: port 0 -> unit -> out;
// forwarding_delay F: port 1..3 -> out; docs/esc.md "Forwarding delays inside
// an ESC"), different per device type. Test values, not datasheet ones; the
// pairs the master halves below add up to even numbers.
constexpr nanoseconds kPc{260}, kFc{140};  // coupler
constexpr nanoseconds kPj{220}, kFj{100};  // junction
constexpr nanoseconds kPs{340}, kFs{300};  // servo

slave::SlaveOptions inner(nanoseconds p, nanoseconds f) {
  slave::SlaveOptions o;
  o.processing_delay = p;
  o.forwarding_delay = f;
  return o;
}

struct Tree : InProcess {
  Tree() {
    add(load("coupler-3port.xml"), inner(kPc, kFc));
    attach("junction-4port.xml", 0, 1, kCJ, inner(kPj, kFj));
    attach("generic-servo.xml", 1, 3, kJA1);
    attach("generic-servo.xml", 2, 1, kA1A2);
    attach("generic-servo.xml", 1, 2, kJB1);
    attach("generic-servo.xml", 4, 1, kB1B2);
    attach("generic-servo.xml", 5, 1, kB2B3);
    attach("generic-servo.xml", 0, 2, kCD);
  }
  void attach(const std::string& file, std::size_t parent, unsigned port, nanoseconds delay,
              const slave::SlaveOptions& o = inner(kPs, kFs)) {
    auto ok = chain.attach(load(file), o, parent, port, esc::kUpstreamPort, delay);
    if (!ok) throw std::runtime_error(ok.error());
  }
};

struct Place {
  std::optional<std::size_t> parent;
  unsigned parent_port;
  unsigned entry_port;
  std::uint8_t active_ports;
};
// The tree as built. Active ports (DL status: open with communication):
// C 0,1,2; J 0,2,3; a servo in the middle of its branch 0,1; at the end 0.
constexpr std::array<Place, 8> kBuilt{{
    {std::nullopt, 0, 0, 0b0111},  // C
    {0, 1, 0, 0b1101},             // J
    {1, 3, 0, 0b0011},             // A1
    {2, 1, 0, 0b0001},             // A2
    {1, 2, 0, 0b0011},             // B1
    {4, 1, 0, 0b0011},             // B2
    {5, 1, 0, 0b0001},             // B3
    {0, 2, 0, 0b0001},             // D
}};

// Expected delays (0x0928), from the cables and the ESCs' inner delays.
// The master (compute_dc_delays, the same terms as SOEM's ecx_configdc) sets
// a slave's delay to its parent's, plus the time the frame spent in the
// parent's earlier branches (entry port to the port before the slave's),
// plus half of (the round trip out of the parent's port and back minus the
// slave's own round trip). That half is the cable plus half of two inner
// times: the parent's from the port before to leaving toward the slave (P
// when that port is the entry port 0: through the unit; else F) and the
// slave's from its last port to leaving back out of port 0 (F when it has
// more open ports; P for a slave at the end of a branch, whose frame turns
// round through its unit). Masters assume forwarding takes as long both ways;
// with P != F the delay they write is that average, not the one-way time.
//   J  = CJ + (Pc + Fj) / 2
//   A1 = J + JA1 + (Pj + Fs) / 2,      A2 = A1 + A1A2 + (Ps + Ps) / 2
//   B1 = J + [Pj + round A] + JB1 + (Fj + Fs) / 2
//        round A = 2 JA1 + Ps + 2 A1A2 + Ps + Fs   (J port 3 out .. in)
//   B2 = B1 + B1B2 + (Ps + Fs) / 2,    B3 = B2 + B2B3 + (Ps + Ps) / 2
//   D  = [Pc + 2 CJ + J's whole time] + CD + (Fc + Ps) / 2
//        J's whole time = Pj + round A + Fj + round B + Fj   (port 0 in .. out)
//        round B = 2 JB1 + Ps + 2 B1B2 + Ps + 2 B2B3 + Ps + Fs + Fs
// With all inner delays 0 these are the cable sums of docs/topology.md
// (J 150, A1 860, A2 1380, B1 3540, B2 3980, B3 4350, D 6850).
constexpr std::int64_t half(nanoseconds a, nanoseconds b) { return (a + b).count() / 2; }
constexpr std::int64_t kRoundA = (2 * kJA1 + kPs + 2 * kA1A2 + kPs + kFs).count();
constexpr std::int64_t kRoundB = (2 * kJB1 + kPs + 2 * kB1B2 + kPs + 2 * kB2B3 + kPs + kFs + kFs).count();
constexpr std::int64_t kJ = kCJ.count() + half(kPc, kFj);
constexpr std::int64_t kA1 = kJ + kJA1.count() + half(kPj, kFs);
constexpr std::int64_t kB1 = kJ + kPj.count() + kRoundA + kJB1.count() + half(kFj, kFs);
constexpr std::int64_t kB2 = kB1 + kB1B2.count() + half(kPs, kFs);
constexpr std::int64_t kJWhole = kPj.count() + kRoundA + kFj.count() + kRoundB + kFj.count();
constexpr std::array<std::int64_t, 8> kDelay{
    0,
    kJ,
    kA1,
    kA1 + kA1A2.count() + half(kPs, kPs),
    kB1,
    kB2,
    kB2 + kB2B3.count() + half(kPs, kPs),
    kPc.count() + 2 * kCJ.count() + kJWhole + kCD.count() + half(kFc, kPs),
};
static_assert((kPc + kFj).count() % 2 == 0 && (kPj + kFs).count() % 2 == 0 && (kFj + kFs).count() % 2 == 0 &&
                  (kPs + kFs).count() % 2 == 0 && (kFc + kPs).count() % 2 == 0,
              "halves without rounding");

TEST(TreeDc, ScanGivesTheTreeAsBuilt) {
  Tree t;
  auto n = t.master.scan();
  ASSERT_TRUE(n);
  ASSERT_EQ(*n, kBuilt.size());
  EXPECT_EQ(t.master.slave(0).sii.product_code, 0x00000C03u);
  EXPECT_EQ(t.master.slave(1).sii.product_code, 0x00000C04u);
  for (std::size_t i = 2; i < kBuilt.size(); ++i) EXPECT_EQ(t.master.slave(i).sii.product_code, 0x00000402u) << i;
  for (std::size_t i = 0; i < kBuilt.size(); ++i) {
    const master::SlaveTopology& got = t.master.slave(i).topology;
    EXPECT_EQ(got.parent, kBuilt[i].parent) << "slave " << i;
    EXPECT_EQ(got.parent_port, kBuilt[i].parent_port) << "slave " << i;
    EXPECT_EQ(got.entry_port, kBuilt[i].entry_port) << "slave " << i;
    EXPECT_EQ(got.active_ports, kBuilt[i].active_ports) << "slave " << i;
    EXPECT_EQ(got.open_end_ports, 0) << "slave " << i;
  }
}

TEST(TreeDc, ConfigureDcWritesTheCableAndInnerDelays) {
  Tree t;
  ASSERT_TRUE(t.master.scan());
  auto dc = t.master.configure_dc(t.clock.now());
  ASSERT_TRUE(dc);
  EXPECT_EQ(*dc, kBuilt.size());  // coupler and junction have DC too (dc64)
  for (std::size_t i = 0; i < kBuilt.size(); ++i) {
    const esc::Esc& e = t.chain[i].esc();
    const std::uint32_t written = e.register_u16(master::reg::kDcSystemTimeDelay) |
                                  (std::uint32_t{e.register_u16(master::reg::kDcSystemTimeDelay + 2)} << 16);
    EXPECT_EQ(written, static_cast<std::uint32_t>(kDelay[i])) << "slave " << i;
    EXPECT_EQ(t.master.slave(i).dc.delay_ns, written) << "slave " << i;
    // The entry ports from the port times agree with DL status.
    EXPECT_EQ(t.master.slave(i).topology.parent, kBuilt[i].parent) << "slave " << i;
    EXPECT_EQ(t.master.slave(i).topology.entry_port, 0u) << "slave " << i;
  }
}

// Link down on the junction's branch port 2 (the B branch) and up again:
// J closes port 2 (Auto), loses its link and communication bits there and
// counts a lost link; B1..B3 drop out of the frame's way; no AL state moves.
TEST(TreeDc, BranchLinkDownAndUpGivesSiliconDlStatus) {
  Tree t;
  ASSERT_TRUE(t.master.scan());
  for (std::size_t i = 0; i < kBuilt.size(); ++i) {
    if (i >= 2) {  // the drives; C and J have no mailbox
      ASSERT_TRUE(t.master.configure_mailbox(i)) << i;
    }
    auto st = t.master.request_state(i, master::AlState::PreOp);
    ASSERT_TRUE(st) << i;
    ASSERT_EQ(st->raw, 0x0002) << i;
  }
  auto& j = t.chain[1].esc();
  // DL status (Section II 0x0110): link bits 4+n, loop closed 8+2n,
  // communication 9+2n. Up: links 0, 2, 3 (0x0D << 4); port 1 closed (bit 10).
  EXPECT_EQ(j.register_u16(esc::reg::kDlStatus) & 0xFFF0, 0xA6D0);
  ASSERT_TRUE(t.chain.segment().set_link(1, 2, false));
  // Port 2: link gone, loop closed (bit 12), no communication: 0x9690 (ports 1, 2 closed).
  EXPECT_EQ(j.register_u16(esc::reg::kDlStatus) & 0xFFF0, 0x9690);
  EXPECT_EQ(j.memory()[esc::reg::kLostLinkCounter + 2], 1);
  EXPECT_EQ(t.chain[4].esc().memory()[esc::reg::kLostLinkCounter + 0], 1);
  // B1's port 0 lost its link: closed, no communication.
  EXPECT_EQ(t.chain[4].esc().register_u16(esc::reg::kDlStatus) & 0x0310, 0x0100);
  // A broadcast read now reaches C, J, A1, A2, D: WKC 5; AL states stay PreOp.
  auto al = t.master.read_al_status(0);
  ASSERT_TRUE(al);
  EXPECT_EQ(al->raw, 0x0002);
  for (std::size_t i = 0; i < kBuilt.size(); ++i) {
    EXPECT_EQ(t.chain[i].esc().register_u16(esc::reg::kAlStatus), 0x0002) << i;
  }
  ASSERT_TRUE(t.chain.segment().set_link(1, 2, true));
  EXPECT_EQ(j.register_u16(esc::reg::kDlStatus) & 0xFFF0, 0xA6D0);
  EXPECT_EQ(j.memory()[esc::reg::kLostLinkCounter + 2], 1);  // counts losses only
  auto again = t.master.scan();
  ASSERT_TRUE(again);
  EXPECT_EQ(*again, kBuilt.size());
  for (std::size_t i = 0; i < kBuilt.size(); ++i) {
    EXPECT_EQ(t.master.slave(i).topology.parent, kBuilt[i].parent) << i;
  }
}

}  // namespace
}  // namespace ecat::test
