// A tree of virtual slaves from the shipped device files (issue 16): the
// coupler and junction files give their port descriptors, the project's
// master scans the tree in the silicon's port order, the coupler follows AL
// control without firmware of its own (device emulation), and a cut branch
// leaves the rest of the tree and every AL state as they were.
#include <gtest/gtest.h>

#include <string>

#include "common/frame_builder.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

od::DeviceDescription load(const std::string& name) {
  auto d = esi::load_device_file(std::string(ECAT_SOURCE_DIR) + "/xml/devices/" + name);
  if (!d) throw std::runtime_error(d.error().to_string());
  return std::move(*d);
}

// coupler (port 1 E-bus) -> junction; junction port 3 -> drive a1 -> a2;
// junction port 2 -> drive b1.
struct TreeRig : InProcess {
  TreeRig() {
    add(load("coupler-3port.xml"));
    attach(load("junction-4port.xml"), 0, 1);
    attach(load("generic-servo.xml"), 1, 3);
    attach(load("generic-servo.xml"), 2, 1);
    attach(load("generic-servo.xml"), 1, 2);
  }
  void attach(od::DeviceDescription d, std::size_t parent, unsigned port) {
    auto ok = chain.attach(std::move(d), {}, parent, port);
    if (!ok) throw std::runtime_error(ok.error());
  }
};

TEST(TopologyChain, DeviceFilesGivePortDescriptors) {
  TreeRig r;
  EXPECT_EQ(r.chain[0].esc().memory()[esc::reg::kPortDescriptor], 0x3B);
  EXPECT_EQ(r.chain[1].esc().memory()[esc::reg::kPortDescriptor], 0xFA);
  EXPECT_EQ(r.chain[2].esc().memory()[esc::reg::kPortDescriptor], 0x0F);
  EXPECT_FALSE(r.chain.segment().is_line());
}

TEST(TopologyChain, MasterScansTheTreeInPortOrder) {
  TreeRig r;
  auto n = r.master.scan();
  ASSERT_TRUE(n);
  ASSERT_EQ(*n, 5u);
  // 0 -> PU -> 3 -> 1 -> 2: coupler, junction, a1, a2 (behind a1), b1.
  EXPECT_EQ(r.master.slave(0).sii.product_code, 0x00000C03u);
  EXPECT_EQ(r.master.slave(1).sii.product_code, 0x00000C04u);
  EXPECT_EQ(r.master.slave(2).sii.product_code, 0x00000402u);
  EXPECT_EQ(r.master.slave(4).sii.product_code, 0x00000402u);
  // The coupler, without a µC, follows AL control by device emulation.
  auto st = r.master.request_state(0, master::AlState::PreOp);
  ASSERT_TRUE(st);
  EXPECT_EQ(st->raw, 0x0002);
  // Cut the branch on the junction's port 3: a1 and a2 drop out, the rest
  // answers; AL states untouched; the junction counted the lost link.
  ASSERT_TRUE(r.chain.segment().set_link(1, 3, false));
  auto again = r.master.read_al_status(0);
  ASSERT_TRUE(again);
  EXPECT_EQ(again->raw, 0x0002);
  EXPECT_EQ(r.chain[1].esc().memory()[esc::reg::kLostLinkCounter + 3], 1);
  EXPECT_EQ(r.chain[2].esc().register_u16(esc::reg::kAlStatus), 0x0001);
  // The DL status of the junction: links 0 and 2 (0x50), ports 1 and 3 closed (bits 10, 14),
  // port 1 not cabled (the junction's E-bus out is free), communication 0 and 2 (9, 13).
  EXPECT_EQ(r.chain[1].esc().register_u16(esc::reg::kDlStatus) & 0xFFF0, 0x6650);
}

TEST(TopologyChain, RingFramesLeaveOnTheRightMasterPort) {
  InProcess p;
  for (int i = 0; i < 3; ++i) p.add(load("generic-servo.xml"));
  ASSERT_TRUE(p.chain.connect_redundant(2, 1));
  EXPECT_FALSE(p.chain.connect_redundant(2, 1));  // one cable per port
  std::array<std::uint8_t, 64> buf{};
  auto frame = [&] {
    buf.fill(0);
    FrameBuilder b(buf, kBroadcastMac, MacAddress{0x02, 0, 0, 0, 0, 1});
    (void)b.append_zeros(Command::Brd, 0, device_address(0, esc::reg::kType), 1);
    return b.finish();
  };
  auto f = frame();
  esc::Delivery d = p.chain.pass_frame_on(f, Nanoseconds{0}, 0);
  EXPECT_TRUE(d.returned());
  EXPECT_EQ(d.master_port, 1u);
  EXPECT_EQ(d.processed, 3u);
  p.chain.segment().set_link(0, 1, false);
  f = frame();
  d = p.chain.pass_frame_on(f, Nanoseconds{0}, 1);
  EXPECT_EQ(d.master_port, 1u);
  EXPECT_EQ(d.processed, 2u);
  EXPECT_EQ(p.chain.stats().frames_returned, 2u);
}

}  // namespace
}  // namespace ecat::test
