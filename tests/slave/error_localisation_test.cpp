// Error localisation by the project's master on the tree of
// xml/topologies/tree.txt (coupler -> junction port 3 -> a1 -> a2, junction
// port 2 -> b1): the cable junction:2 - b1:0 corrupts three frames
// (esc::Segment::corrupt_link); the frames are lost to the master; then the
// master reads 0x0300-0x0313 of every slave, as TwinCAT's and SOEM's
// diagnosis do, and finds the broken cable in front of the one slave that
// counts the error as its own (0x0300+2n, not forwarded: Section I §14.2;
// ET1100 application note "error counter interpretation": the cable in front
// of the slave whose own CRC error counter increases).
#include <gtest/gtest.h>

#include <array>
#include <string>

#include "esc/registers.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

constexpr std::size_t kCoupler = 0, kJunction = 1, kA1 = 2, kA2 = 3, kB1 = 4;
constexpr std::uint16_t kCounters = 0x0300;
constexpr std::size_t kCounterBytes = 0x14;  // 0x0300-0x0313

od::DeviceDescription load(const std::string& name) {
  auto d = esi::load_device_file(std::string(ECAT_SOURCE_DIR) + "/xml/devices/" + name);
  if (!d) throw std::runtime_error(d.error().to_string());
  return std::move(*d);
}

struct TreeWithLostFrames : InProcess {
  TreeWithLostFrames() {
    add(load("coupler-3port.xml"));
    attach("junction-4port.xml", kCoupler, 1);
    attach("generic-servo.xml", kJunction, 3);
    attach("generic-servo.xml", kA1, 1);
    attach("generic-servo.xml", kJunction, 2);
    // A frame that does not come back intact (corrupted: bad FCS) is lost.
    wire.set_processor([this](Bytes frame) {
      clock.advance(kWireTime);
      if (!chain.process_frame(frame, clock.now())) wire.drop_next(1);
    });
  }
  void attach(const std::string& file, std::size_t parent, unsigned port) {
    auto ok = chain.attach(load(file), {}, parent, port);
    if (!ok) throw std::runtime_error(ok.error());
  }
};

using Counters = std::array<std::uint8_t, kCounterBytes>;
Counters with(std::initializer_list<std::pair<std::uint16_t, std::uint8_t>> values) {
  Counters c{};
  for (auto [reg, v] : values) c[static_cast<std::size_t>(reg - kCounters)] = v;
  return c;
}

TEST(ErrorLocalisation, MasterFindsTheCorruptingCable) {
  TreeWithLostFrames t;
  auto n = t.master.scan();
  ASSERT_TRUE(n);
  ASSERT_EQ(*n, 5u);
  ASSERT_TRUE(t.chain.segment().corrupt_link(kJunction, 2, 3));
  // Three frames go out and do not come back (the master sends again what
  // it does not get back, so its reads still succeed).
  const std::uint64_t lost_before = t.chain.stats().frames_lost;
  for (int i = 0; i < 10 && t.chain.segment().corruption_pending(kJunction, 2) != 0; ++i) {
    (void)t.master.read_al_status(kCoupler);
  }
  EXPECT_EQ(t.chain.segment().corruption_pending(kB1, 0), 0u);
  EXPECT_EQ(t.chain.stats().frames_lost - lost_before, 3u);
  EXPECT_TRUE(t.master.read_al_status(kCoupler));  // the cable is good again

  std::array<Counters, 5> got{};
  for (std::size_t i = 0; i < got.size(); ++i) {
    ASSERT_TRUE(t.master.fprd(t.master.slave(i).station_address, kCounters, got[i])) << i;
  }
  // The frame's way: C PU, C:1 -> J PU, J:3 -> a1, a2 and back, J:2 -> the
  // cable (hit) -> b1:0 (own error 0x0300, unit 0x030C) -> back into J:2
  // (forwarded 0x030A) -> J:0 -> C:1 (forwarded 0x0309) -> C:0 -> master.
  EXPECT_EQ(got[kCoupler], with({{0x0309, 3}}));
  EXPECT_EQ(got[kJunction], with({{0x030A, 3}}));
  EXPECT_EQ(got[kA1], Counters{});
  EXPECT_EQ(got[kA2], Counters{});
  EXPECT_EQ(got[kB1], with({{0x0300, 3}, {0x030C, 3}}));

  // Localisation: the slave with an own (not forwarded) error at port p;
  // the cable is the one on that port, to its parent when p is its entry port.
  std::optional<std::size_t> at;
  unsigned port = 0;
  for (std::size_t i = 0; i < got.size() && !at; ++i) {
    for (unsigned p = 0; p < 4; ++p) {
      if (got[i][2 * p] != 0) {
        at = i;
        port = p;
        break;
      }
    }
  }
  ASSERT_TRUE(at);
  EXPECT_EQ(*at, kB1);
  EXPECT_EQ(port, t.master.slave(kB1).topology.entry_port);
  EXPECT_EQ(t.master.slave(kB1).topology.parent, kJunction);
  EXPECT_EQ(t.master.slave(kB1).topology.parent_port, 2u);  // the cable junction:2 - b1:0
}

}  // namespace
}  // namespace ecat::test
