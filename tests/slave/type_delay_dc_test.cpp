// Inner delays from the ESC type (issue 16 item 1, docs/esc.md "Forwarding
// delay figures per ESC type"): each slave's processing and per-port
// forwarding delays come from its device's ESC type (0x0000) and port types
// (0x0007, E-bus or MII) through a figures table; the receive-time latches
// 0x0900-0x090F and the delays the project's master writes to 0x0928 are the
// cables plus those figures summed along the frame's path. No datasheet
// figure could be sourced, so the table here holds test values under a type
// code no real ESC has; the shipped table gives 0 for every type (the cable
// sums), and SlaveOptions still override a slave's figures.
#include <gtest/gtest.h>

#include <array>
#include <string>

#include "master/registers.hpp"
#include "slave/esc_setup.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

using std::chrono::nanoseconds;

constexpr std::uint8_t kTestType = 0xEE;
// Test values (not a datasheet's): through the unit / alongside it, by the
// type of the port the frame enters.
constexpr nanoseconds kPebus{260}, kPmii{340}, kFebus{120}, kFmii{180};
constexpr esc::InnerDelayFigures kFigures[] = {
    {kTestType, "test ESC", kPebus, kPmii, kFebus, kFmii, "test values"},
};

od::DeviceDescription load(const std::string& name, std::uint8_t esc_type) {
  auto d = esi::load_device_file(std::string(ECAT_SOURCE_DIR) + "/xml/devices/" + name);
  if (!d) throw std::runtime_error(d.error().to_string());
  d->esc.esc_type = esc_type;
  return std::move(*d);
}

// Positions, in the order the frame meets them:
//   0 C coupler-3port  (YKY: port 0 MII, 1 E-bus, 2 MII) on the master
//   1 J junction-4port (KKYY: ports 0, 1 E-bus, 2, 3 MII) on C port 1, cable CJ
//   2 A generic-servo  (YY) on J port 3, cable JA
//   3 B generic-servo  (YY) on C port 2, cable CB
constexpr nanoseconds kCJ{150}, kJA{710}, kCB{610};

struct TypedTree : InProcess {
  explicit TypedTree(std::uint8_t type, std::span<const esc::InnerDelayFigures> figures,
                     slave::SlaveOptions b = {}) {
    slave::SlaveOptions o;
    o.delay_figures = figures;
    b.delay_figures = figures;
    add(load("coupler-3port.xml", type), o);
    attach(load("junction-4port.xml", type), o, 0, 1, kCJ);
    attach(load("generic-servo.xml", type), o, 1, 3, kJA);
    attach(load("generic-servo.xml", type), b, 0, 2, kCB);
  }
  void attach(od::DeviceDescription d, const slave::SlaveOptions& o, std::size_t parent, unsigned port,
              nanoseconds delay) {
    auto ok = chain.attach(std::move(d), o, parent, port, esc::kUpstreamPort, delay);
    if (!ok) throw std::runtime_error(ok.error());
  }
  // Scans, configures DC (latch, read 0x0900.., write 0x0928); the written delays.
  std::array<std::uint32_t, 4> configure() {
    if (!master.scan()) throw std::runtime_error("scan");
    auto dc = master.configure_dc(clock.now());
    if (!dc || *dc != 4) throw std::runtime_error("configure_dc");
    std::array<std::uint32_t, 4> written{};
    for (std::size_t i = 0; i < written.size(); ++i) {
      const esc::Esc& e = chain[i].esc();
      written[i] = e.register_u16(master::reg::kDcSystemTimeDelay) |
                   (std::uint32_t{e.register_u16(master::reg::kDcSystemTimeDelay + 2)} << 16);
    }
    return written;
  }
  std::int64_t port_diff(std::size_t slave, unsigned later, unsigned earlier) {
    const auto& t = master.slave(slave).dc.port_receive_time;
    return static_cast<std::int64_t>(t[later] - t[earlier]);
  }
};

// Each ESC's delays from its type's figures and its ports.
TEST(TypeDelay, EscConfigTakesTheFiguresOfItsTypeAndPorts) {
  auto coupler = slave::esc_config_for(load("coupler-3port.xml", kTestType), kFigures);
  ASSERT_TRUE(coupler);
  EXPECT_EQ(coupler->processing_delay, kPmii);
  EXPECT_EQ(coupler->port_forwarding_delay[1], kFebus);
  EXPECT_EQ(coupler->port_forwarding_delay[2], kFmii);
  EXPECT_EQ(coupler->port_forwarding_delay[3], nanoseconds{0});  // not implemented
  auto junction = slave::esc_config_for(load("junction-4port.xml", kTestType), kFigures);
  ASSERT_TRUE(junction);
  EXPECT_EQ(junction->processing_delay, kPebus);
  EXPECT_EQ(junction->port_forwarding_delay[1], kFebus);
  EXPECT_EQ(junction->port_forwarding_delay[3], kFmii);
  // A type the table does not name keeps 0 and no per-port figure.
  auto other = slave::esc_config_for(load("coupler-3port.xml", 0x11), kFigures);
  ASSERT_TRUE(other);
  EXPECT_EQ(other->processing_delay, nanoseconds{0});
  EXPECT_FALSE(other->port_forwarding_delay[1]);
}

// The latches: C's port 1 sees the frame back after J's whole branch, its
// port 2 after B's; J's port 3 after A's. Each difference is the figures and
// cables on the way, summed:
//   C1 - C0 = Pc + 2 CJ + Pj + 2 JA + Pa + Fj(3)      (C: P MII; J: P E-bus, F MII at port 3; A: P MII)
//   C2 - C1 = Fc(1) + 2 CB + Pb                        (C: F E-bus at port 1; B: P MII)
//   J3 - J0 = Pj + 2 JA + Pa
// and the master's delays (compute_dc_delays, SOEM's terms; docs/esc.md):
//   J = CJ + (Pc + Fj(3)) / 2
//   A = J + JA + (Pj + Pa) / 2
//   B = Pc + 2 CJ + (Pj + 2 JA + Pa + Fj(3)) + CB + (Fc(1) + Pb) / 2
TEST(TypeDelay, LatchesAndMasterDelaysSumTheTypeFigures) {
  TypedTree t(kTestType, kFigures);
  const auto written = t.configure();
  const std::int64_t pc = kPmii.count(), pj = kPebus.count(), pa = kPmii.count(), pb = kPmii.count();
  const std::int64_t fj3 = kFmii.count(), fc1 = kFebus.count();
  const std::int64_t cj = kCJ.count(), ja = kJA.count(), cb = kCB.count();
  EXPECT_EQ(t.port_diff(0, 1, 0), pc + 2 * cj + pj + 2 * ja + pa + fj3);
  EXPECT_EQ(t.port_diff(0, 2, 1), fc1 + 2 * cb + pb);
  EXPECT_EQ(t.port_diff(1, 3, 0), pj + 2 * ja + pa);
  EXPECT_EQ(t.port_diff(0, 1, 0), 2840);  // written out
  EXPECT_EQ(t.port_diff(0, 2, 1), 1680);
  EXPECT_EQ(t.port_diff(1, 3, 0), 2020);
  const std::int64_t j = cj + (pc + fj3) / 2;
  const std::int64_t a = j + ja + (pj + pa) / 2;
  const std::int64_t b = pc + 2 * cj + (pj + 2 * ja + pa + fj3) + cb + (fc1 + pb) / 2;
  EXPECT_EQ(written, (std::array<std::uint32_t, 4>{0, static_cast<std::uint32_t>(j), static_cast<std::uint32_t>(a),
                                                    static_cast<std::uint32_t>(b)}));
  EXPECT_EQ(written, (std::array<std::uint32_t, 4>{0, 410, 1420, 3680}));
}

// The shipped figures: no type has a sourced figure, so the device files'
// type gives 0 inside every ESC and the delays are the cable sums.
TEST(TypeDelay, ShippedFiguresLeaveTheCableSums) {
  TypedTree t(od::EscProperties{}.esc_type, esc::datasheet_inner_delays());
  const auto written = t.configure();
  EXPECT_EQ(t.port_diff(0, 1, 0), 2 * (150 + 710));
  EXPECT_EQ(t.port_diff(0, 2, 1), 2 * 610);
  EXPECT_EQ(written, (std::array<std::uint32_t, 4>{0, 150, 150 + 710, 2 * 150 + 2 * 710 + 610}));
}

// A slave's own figures (SlaveOptions, ecat-slave's `inner P F`) win over
// its type's: B's processing delay 500 instead of P MII; its forwarding
// delay is never on the path (B is a branch end).
TEST(TypeDelay, SlaveOptionsOverrideTheTypeFigures) {
  slave::SlaveOptions b;
  b.processing_delay = nanoseconds{500};
  b.forwarding_delay = nanoseconds{40};
  TypedTree t(kTestType, kFigures, b);
  const auto written = t.configure();
  EXPECT_EQ(t.port_diff(0, 2, 1), kFebus.count() + 2 * kCB.count() + 500);
  EXPECT_EQ(written[3], 340u + 300u + (260u + 1420u + 340u + 180u) + 610u + (120u + 500u) / 2);
  const esc::EscConfig& cfg = t.chain[3].esc().config();
  EXPECT_EQ(cfg.forwarding_delay, nanoseconds{40});
  EXPECT_FALSE(cfg.port_forwarding_delay[1]);  // the option replaces the per-port figures
}

}  // namespace
}  // namespace ecat::test
