// The network view's topology and frame counters (issue 27: the browser page
// draws the tree from each port's "peer" and shows the frame statistics):
// exact JSON for a line of two slaves, a cut cable and the chain's counters.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "control/request_handler.hpp"
#include "slave/fault_catalogue.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

using nlohmann::json;

struct ViewRig : InProcess {
  control::EventQueue events;
  slave::FaultCatalogue faults{chain};
  control::RequestHandler handler{chain, clock, events, &faults};
  ViewRig() { add_default(2); }
  json network() { return handler.handle({{"cmd", "network"}})["result"]; }
};

json peers(const json& slave) {
  json out = json::array();
  for (const json& p : slave["ports"]) out.push_back(p["peer"]);
  return out;
}

TEST(ControlNetworkView, EachPortNamesWhatItsCableGoesTo) {
  ViewRig rig;
  ASSERT_EQ(rig.bring_up(), "");
  const json net = rig.network();
  EXPECT_EQ(peers(net["slaves"][0]), json::parse(R"j([{"master":0},{"slave":1,"port":0},null,null])j"));
  EXPECT_EQ(peers(net["slaves"][1]), json::parse(R"j([{"slave":0,"port":1},null,null,null])j"));
  EXPECT_EQ(rig.handler.handle({{"cmd", "slave"}, {"slave", 1}})["result"], net["slaves"][1]);
}

TEST(ControlNetworkView, ACutCableKeepsItsPeerAndLosesTheLink) {
  ViewRig rig;
  ASSERT_EQ(rig.bring_up(), "");
  const json engaged =
      rig.handler.handle({{"cmd", "fault_engage"}, {"kind", "link_cut"}, {"slave", 0}, {"port", 1}});
  ASSERT_TRUE(engaged.contains("result")) << engaged.dump();
  const json net = rig.network();
  EXPECT_EQ(net["slaves"][0]["ports"][1]["peer"], json::parse(R"j({"slave":1,"port":0})j"));
  EXPECT_EQ(net["slaves"][0]["ports"][1]["link"], false);
  EXPECT_EQ(net["slaves"][1]["ports"][0]["link"], false);
}

TEST(ControlNetworkView, FrameCountersAreTheChainsOwn) {
  ViewRig rig;
  ASSERT_EQ(rig.bring_up(), "");
  const slave::ChainStats& s = rig.chain.stats();
  ASSERT_GT(s.frames_received, 0u);
  const json expected = {{"received", s.frames_received}, {"returned", s.frames_returned},
                         {"malformed", s.frames_malformed}, {"lost", s.frames_lost},
                         {"stale", s.frames_stale},        {"datagrams", s.datagrams},
                         {"wkc_total", s.wkc_total},
                         // bring_up's 10 cycles in SafeOp, 1 ms + 5 us of wire time apart
                         {"cycles", 10},
                         {"cycle_period_ns", 1'005'000},
                         {"lateness",
                          {{"early", 0},
                           {"on_time", 9},
                           {"late_10_25", 0},
                           {"late_25_50", 0},
                           {"missed_1", 0},
                           {"missed_2_or_more", 0}}},
                         {"lateness_unsorted", 0}};
  EXPECT_EQ(rig.network()["frames"], expected);
}

}  // namespace
}  // namespace ecat::test
