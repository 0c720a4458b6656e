// Events of the control interface (control::EventWatcher, control::EventQueue):
// what the master does to a slave - AL control requests, state changes, SDO
// writes - and what the slave sends - emergencies - found on a sample after
// it happened, with the exact codes and values; the queue keeps the newest
// and says how many a late reader lost.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "control/event_queue.hpp"
#include "control/event_watcher.hpp"
#include "master/coe_client.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

using nlohmann::json;

// The events without their time stamps (simulated, but not what is tested here).
json untimed(json events) {
  for (json& e : events) e.erase("time_ns");
  return events;
}

TEST(ControlEvents, NothingHappenedNothingReported) {
  InProcess p;
  p.add_default(2);
  control::EventQueue q;
  control::EventWatcher w(p.chain);
  p.advance(std::chrono::milliseconds(10));
  w.sample(p.clock.now(), q);
  EXPECT_EQ(q.next_seq(), 0u);
}

TEST(ControlEvents, MasterRequestsAndSdoWritesAndEmergencies) {
  InProcess p;
  p.add_default(2);
  control::EventQueue q;
  control::EventWatcher w(p.chain);
  ASSERT_TRUE(p.master.scan());
  ASSERT_TRUE(p.master.configure_mailbox(1));
  ASSERT_TRUE(p.master.request_state(1, master::AlState::PreOp));
  w.sample(p.clock.now(), q);
  // scan() wrote AL control Init + error acknowledge (0x11) to every
  // slave; slave 1 was then asked for PreOp and went there. One sample
  // sees each register's last value: slave 1's 0x11 was overwritten.
  EXPECT_EQ(untimed(q.since(0, 100)["events"]), json::parse(R"j([
    {"seq":0,"type":"al_control","slave":0,"requested":"INIT","error_ack":true,"al_control":17},
    {"seq":1,"type":"al_control","slave":1,"requested":"PREOP","error_ack":false,"al_control":2},
    {"seq":2,"type":"al_state","slave":1,"from":"INIT","to":"PREOP","error":false,"al_status_code":0,
     "al_status_code_text":"No error"}])j"));
  master::CoeClient coe(p.master, 1);
  ASSERT_TRUE(coe.download_value(0x6065, 0, 5000, 4));  // following error window
  ASSERT_TRUE(coe.download_value(0x6066, 0, 20, 2));
  auto& emcy = p.chain[1].firmware().coe().emergency();
  ASSERT_TRUE(emcy.raise(0x4310, 0x09));  // temperature, drive
  w.sample(p.clock.now(), q);
  EXPECT_EQ(untimed(q.since(3, 100)["events"]), json::parse(R"j([
    {"seq":3,"type":"sdo_write","slave":1,"index":24677,"subindex":0,"value":5000},
    {"seq":4,"type":"sdo_write","slave":1,"index":24678,"subindex":0,"value":20},
    {"seq":5,"type":"emergency","slave":1,"error_code":17168,"error_register":9}])j"));
  // Sampled again with nothing new: nothing more.
  w.sample(p.clock.now(), q);
  EXPECT_EQ(q.next_seq(), 6u);
}

TEST(ControlEvents, QueueKeepsTheNewestAndCountsWhatALateReaderLost) {
  control::EventQueue q(3);
  for (int i = 0; i < 5; ++i) q.push({{"type", "x"}, {"n", i}});
  EXPECT_EQ(q.first_seq(), 2u);
  EXPECT_EQ(q.since(0, 100), json::parse(R"j({"events":[{"n":2,"seq":2,"type":"x"},{"n":3,"seq":3,"type":"x"},
                                                {"n":4,"seq":4,"type":"x"}],"next":5,"lost":2})j"));
  EXPECT_EQ(q.since(3, 1), json::parse(R"j({"events":[{"n":3,"seq":3,"type":"x"}],"next":4,"lost":0})j"));
  EXPECT_EQ(q.since(9, 10), json::parse(R"j({"events":[],"next":5,"lost":0})j"));
}

}  // namespace
}  // namespace ecat::test
