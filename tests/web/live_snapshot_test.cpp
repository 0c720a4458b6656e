// The page's snapshot (web/live_snapshot.hpp): the same network as the
// control interface's "network" command at every take, while slave views
// whose registers did not change are copied, not built again (issue 27 item
// 6: the loop pays for the snapshot).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "control/request_handler.hpp"
#include "esi/device_loader.hpp"
#include "slave/fault_catalogue.hpp"
#include "tests/slave/inprocess_fixture.hpp"
#include "web/live_snapshot.hpp"

namespace ecat::test {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;

struct SnapshotRig : InProcess {
  control::EventQueue events;
  slave::FaultCatalogue faults{chain};
  control::RequestHandler handler{chain, clock, events, &faults};
  web::LiveSnapshot snapshot{handler};
  SnapshotRig() { add_default(3); }
  json network() { return handler.handle({{"cmd", "network"}})["result"]; }
  json take() { return json::parse(snapshot.take()); }
};

TEST(WebLiveSnapshot, IsTheControlInterfacesNetworkAtEveryTake) {
  SnapshotRig rig;
  ASSERT_EQ(rig.bring_up(), "");
  json snap = rig.take();
  EXPECT_EQ(snap["network"], rig.network());
  EXPECT_EQ(snap["time_ns"], rig.clock.now().count());
  EXPECT_EQ(snap["faults"], json::array());
  EXPECT_EQ(rig.snapshot.views_built(), 3u);

  // Cycles move the counters and the drives' values, not the views.
  for (int c = 0; c < 5; ++c) ASSERT_TRUE(rig.cycle_once(1ms));
  snap = rig.take();
  EXPECT_EQ(snap["network"], rig.network());
  EXPECT_EQ(rig.snapshot.views_built(), 3u) << "nothing a view shows but the cycle counter changed";
  ASSERT_EQ(snap["drives"].size(), 3u);
  EXPECT_EQ(snap["drives"][1]["slave"], 1);
  const json read = rig.handler.handle({{"cmd", "read"}, {"slave", 1}, {"index", 0x6041}, {"subindex", 0}});
  EXPECT_EQ(snap["drives"][1]["statusword"], read["result"]["value"]) << read.dump();

  // A cut cable: the two slaves at its ends are built again, the third copied.
  ASSERT_TRUE(rig.handler.handle({{"cmd", "fault_engage"}, {"kind", "link_cut"}, {"slave", 1}, {"port", 1}})
                  .contains("result"));
  snap = rig.take();
  EXPECT_EQ(snap["network"], rig.network());
  EXPECT_EQ(snap["network"]["slaves"][1]["ports"][1]["link"], false);
  EXPECT_EQ(snap["network"]["slaves"][2]["ports"][0]["link"], false);
  EXPECT_EQ(snap["faults"].size(), 1u);
  EXPECT_EQ(rig.snapshot.views_built(), 5u);

  // The watchdog of the cut-off slave expires: its AL status and counters change.
  for (int c = 0; c < 150; ++c) (void)rig.cycle_once(1ms);
  snap = rig.take();
  EXPECT_EQ(snap["network"], rig.network());
  EXPECT_EQ(snap["network"]["slaves"][2]["al_status_code"], 0x001B);
}

TEST(WebLiveSnapshot, BeforeAnyMasterTheDrivesAreListedWithTheirValues) {
  SnapshotRig rig;
  const json snap = rig.take();
  EXPECT_EQ(snap["drives"].size(), 3u);
  EXPECT_EQ(snap["network"], rig.network());
  EXPECT_EQ(snap["drives"][0]["slave"], 0);
  EXPECT_TRUE(snap["drives"][0]["mode"].is_number());
}

// A two-axis drive (CiA 402-1 §6): one entry per axis, axis 2's values from
// its own objects at +800h (6841h, 6861h, ...), as "read" gives them.
TEST(WebLiveSnapshot, EachAxisOfAMultiAxisDriveHasItsEntry) {
  ManualClock clock;
  slave::Chain chain{clock};
  auto d = esi::load_device_file(std::string(ECAT_SOURCE_DIR) + "/xml/devices/welcon-servo-dual.xml");
  ASSERT_TRUE(d) << d.error().to_string();
  ASSERT_TRUE(d->drive);
  ASSERT_EQ(d->drive->axes.axes, 2u);
  ASSERT_TRUE(chain.add(std::move(*d), {}));
  control::EventQueue events;
  control::RequestHandler handler{chain, clock, events, nullptr};
  // Axis 2 gets a mode and a position of its own, so that the entries differ.
  for (const auto& [index, value] : {std::pair{0x6860, 9}, std::pair{0x6864, 12345}}) {
    ASSERT_TRUE(handler.handle({{"cmd", "write"}, {"slave", 0}, {"index", index}, {"subindex", 0}, {"value", value}})
                    .contains("result"));
  }
  web::LiveSnapshot snapshot{handler};
  const json drives = json::parse(snapshot.take())["drives"];
  ASSERT_EQ(drives.size(), 2u) << drives.dump();
  for (unsigned axis = 1; axis <= 2; ++axis) {
    const json& e = drives[axis - 1];
    EXPECT_EQ(e["slave"], 0);
    EXPECT_EQ(e["axis"], axis);
    const int offset = static_cast<int>(axis - 1) * 0x800;
    for (const auto& [key, index] : {std::pair{"statusword", 0x6041}, std::pair{"mode", 0x6061},
                                     std::pair{"position_actual", 0x6064}}) {
      const json read = handler.handle({{"cmd", "read"}, {"slave", 0}, {"index", index + offset}, {"subindex", 0}});
      EXPECT_EQ(e[key], read["result"]["value"]) << "axis " << axis << " " << key << ": " << read.dump();
    }
  }
  EXPECT_EQ(drives[1]["position_actual"], 12345);
  EXPECT_NE(drives[0]["position_actual"], drives[1]["position_actual"]);
}

}  // namespace
}  // namespace ecat::test
