// Forwarding delays per receiving port (EscConfig::port_forwarding_delay:
// E-bus and MII ports differ) and the per-ESC-type figures they come from
// (esc/inner_delay_figures.hpp; docs/esc.md "Forwarding delay figures per ESC
// type"). Exact times in ns on the receive-time latches 0x0900-0x090F.
#include <gtest/gtest.h>

#include <memory>
#include <set>
#include <vector>

#include "esc/inner_delay_figures.hpp"
#include "esc_fixture.hpp"

namespace ecat::esc::test {
namespace {

// Test values, not datasheet ones (no datasheet figure was found: docs/esc.md).
constexpr Nanoseconds kP{300}, kFebus{120}, kFmii{410};
constexpr Nanoseconds kCableE{150}, kCableM{700};
constexpr std::uint8_t kCouplerPorts = 0x3B;   // port 0 MII, 1 E-bus, 2 MII, 3 not implemented
constexpr std::uint8_t kJunctionPorts = 0xFA;  // ports 0, 1 E-bus, 2, 3 MII

std::uint32_t u32(Esc& e, std::uint16_t a) {
  return e.register_u16(a) | (std::uint32_t{e.register_u16(static_cast<std::uint16_t>(a + 2))} << 16);
}
std::array<std::uint32_t, 4> receive_times(Esc& e) {
  return {u32(e, reg::kDcBase), u32(e, reg::kDcBase + 4), u32(e, reg::kDcBase + 8), u32(e, reg::kDcBase + 12)};
}

Data latch_frame() {
  Segment scratch;
  TestFrame f;
  f.add(Command::Bwr, device_address(0, reg::kDcBase), 4);
  f.send(scratch);
  return Data(f.frame().begin(), f.frame().end());
}

// The coupler `c` with an E-bus device on port 1 (cable kCableE) and an
// MII device on port 2 (cable kCableM).
struct CouplerWithTwo {
  explicit CouplerWithTwo(const EscConfig& c) : coupler(c, clock), e(make_config(), clock), m(make_config(), clock) {
    segment.add(coupler);
    segment.add(e, 0, 1, kUpstreamPort, kCableE);
    segment.add(m, 0, 2, kUpstreamPort, kCableM);
  }
  ManualClock clock;
  Esc coupler;
  Esc e;
  Esc m;
  Segment segment;
};

// A coupler whose E-bus port 1 and MII port 2 forward with different delays,
// an ESC without inner delays on each: the frame goes 0 -> unit (P) -> port 1
// (port 3 absent) -> E and back -> port 1 forwarded (F E-bus) -> port 2 -> M
// and back -> port 2 forwarded (F MII) -> port 0 -> master.
TEST(EscPortDelay, ForwardingDelayFollowsThePortOfEntry) {
  EscConfig c = make_config();
  c.port_descriptor = kCouplerPorts;
  c.processing_delay = kP;
  c.forwarding_delay = Nanoseconds{9999};  // replaced on ports 1 and 2
  c.port_forwarding_delay[1] = kFebus;
  c.port_forwarding_delay[2] = kFmii;
  CouplerWithTwo t(c);
  Esc& coupler = t.coupler;
  Data f = latch_frame();
  const Delivery d = t.segment.send(f, 0ns);
  ASSERT_TRUE(d.returned());
  const std::uint32_t at_e = 300 + 150;           // P + cable
  const std::uint32_t back_1 = at_e + 150;        // E turns it round in 0
  const std::uint32_t at_m = back_1 + 120 + 700;  // F E-bus + cable
  const std::uint32_t back_2 = at_m + 700;
  using T = std::array<std::uint32_t, 4>;
  EXPECT_EQ(receive_times(coupler), (T{0, back_1, back_2, 0}));
  EXPECT_EQ(receive_times(t.e), (T{at_e, 0, 0, 0}));
  EXPECT_EQ(receive_times(t.m), (T{at_m, 0, 0, 0}));
  EXPECT_EQ(d.at.count(), back_2 + 410);  // F MII, the master's cable 0
  EXPECT_EQ(d.at.count(), 2530);          // P + 2 cE + F_E + 2 cM + F_M, written out
}

// A port without its own figure forwards with forwarding_delay.
TEST(EscPortDelay, UnsetPortTakesTheCommonForwardingDelay) {
  EscConfig c = make_config();
  c.port_descriptor = kCouplerPorts;
  c.forwarding_delay = Nanoseconds{90};
  c.port_forwarding_delay[2] = kFmii;  // port 1 unset
  CouplerWithTwo t(c);
  Data f = latch_frame();
  EXPECT_EQ(t.segment.send(f, 0ns).at.count(), 2 * 150 + 90 + 2 * 700 + 410);
}

TEST(InnerDelayFigures, PortTypesFromThePortDescriptor) {
  using A = std::array<PortType, kMaxPorts>;
  EXPECT_EQ(port_types(kCouplerPorts), (A{PortType::Mii, PortType::Ebus, PortType::Mii, PortType::NotImplemented}));
  EXPECT_EQ(port_types(kJunctionPorts), (A{PortType::Ebus, PortType::Ebus, PortType::Mii, PortType::Mii}));
  EXPECT_EQ(port_types(0x0F), (A{PortType::Mii, PortType::Mii, PortType::NotImplemented, PortType::NotImplemented}));
}

// An ESC type's figures per port type: processing by port 0's type,
// forwarding by each port's type, a missing figure and a port that is not
// implemented 0; a type the table does not name gives 0 everywhere.
TEST(InnerDelayFigures, DefaultsFollowTheTypeAndThePortTypes) {
  constexpr std::uint8_t kTestType = 0xEE;  // no real ESC
  const InnerDelayFigures table[] = {
      {kTestType, "test", Nanoseconds{260}, Nanoseconds{340}, Nanoseconds{120}, Nanoseconds{180}, "test values"},
      {0xED, "partial", std::nullopt, Nanoseconds{500}, std::nullopt, Nanoseconds{70}, "test values"},
  };
  const InnerDelays coupler = inner_delays_for(find_inner_delays(table, kTestType), port_types(kCouplerPorts));
  EXPECT_EQ(coupler.processing, Nanoseconds{340});  // port 0 MII
  EXPECT_EQ(coupler.forwarding, (std::array<Nanoseconds, 4>{0ns, 120ns, 180ns, 0ns}));
  const InnerDelays junction = inner_delays_for(find_inner_delays(table, kTestType), port_types(kJunctionPorts));
  EXPECT_EQ(junction.processing, Nanoseconds{260});  // port 0 E-bus
  EXPECT_EQ(junction.forwarding, (std::array<Nanoseconds, 4>{0ns, 120ns, 180ns, 180ns}));
  const InnerDelays partial = inner_delays_for(find_inner_delays(table, 0xED), port_types(kJunctionPorts));
  EXPECT_EQ(partial.processing, 0ns);  // no E-bus figure
  EXPECT_EQ(partial.forwarding, (std::array<Nanoseconds, 4>{0ns, 0ns, 70ns, 70ns}));
  EXPECT_EQ(find_inner_delays(table, 0x11), nullptr);
  const InnerDelays none = inner_delays_for(nullptr, port_types(kJunctionPorts));
  EXPECT_EQ(none.processing, 0ns);
  EXPECT_EQ(none.forwarding, (std::array<Nanoseconds, 4>{}));
}

// The shipped table: one entry per ESC type, each naming its source; an
// entry whose source says "not found" carries no figure (docs/esc.md: no
// figure from memory). Today that is every entry, so every type defaults to
// 0 and the cables carry the time.
TEST(InnerDelayFigures, ShippedTableHasNoUnsourcedFigure) {
  std::set<std::uint8_t> types;
  for (const InnerDelayFigures& f : datasheet_inner_delays()) {
    EXPECT_TRUE(types.insert(f.esc_type).second) << int{f.esc_type};
    EXPECT_FALSE(f.source.empty()) << f.name;
    EXPECT_FALSE(f.name.empty());
    const bool any = f.processing_ebus || f.processing_mii || f.forwarding_ebus || f.forwarding_mii;
    if (f.source.starts_with("not found")) {
      EXPECT_FALSE(any) << f.name;
    }
  }
  for (std::uint8_t t : {kEscTypeEsc20, kEscTypeIpCore, kEscTypeEt1100, kEscTypeEt1200, kEscTypeTi,
                         kEscTypeInfineon, kEscTypeRenesas, kEscTypeMicrochip}) {
    const InnerDelayFigures* f = find_inner_delays(datasheet_inner_delays(), t);
    ASSERT_NE(f, nullptr) << int{t};
    const InnerDelays d = inner_delays_for(f, port_types(kJunctionPorts));
    EXPECT_EQ(d.processing, 0ns) << f->name;
    EXPECT_EQ(d.forwarding, (std::array<Nanoseconds, 4>{})) << f->name;
  }
}

}  // namespace
}  // namespace ecat::esc::test
