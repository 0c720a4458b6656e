// The control interface's request handler (issue 26 item 1, docs/control.md):
// exact replies for the network view, object and process-data access, the
// fault commands and simulated time, and every kind of bad input answered
// with its error code while nothing changes.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "control/request_handler.hpp"
#include "control/simulated_run.hpp"
#include "master/coe_client.hpp"
#include "slave/fault_catalogue.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

using nlohmann::json;

struct Rig : InProcess {
  control::EventQueue events;
  slave::FaultCatalogue faults{chain};
  std::unique_ptr<control::RequestHandler> handler;

  explicit Rig(std::size_t n = 2) {
    add_default(n);
    handler = std::make_unique<control::RequestHandler>(chain, clock, events, &faults);
  }
  json ask(const json& request) { return handler->handle(request); }
  json result(const json& request) {
    json r = ask(request);
    EXPECT_TRUE(r.contains("result")) << r.dump();
    return r.value("result", json());
  }
  // The error code of a refused request.
  std::string refused(const json& request) {
    json r = ask(request);
    EXPECT_TRUE(r.contains("error")) << r.dump();
    return r.contains("error") ? r["error"]["code"].get<std::string>() : std::string("(none)");
  }
  std::int32_t position(std::size_t i) {
    return chain[i].firmware().coe().objects().get<std::int32_t>(0x6064, 0);
  }
};

TEST(ControlHandler, HelloNamesTheProtocolAndWhatThisNetworkHas) {
  Rig rig;
  EXPECT_EQ(rig.ask({{"id", 1}, {"cmd", "hello"}}),
            json::parse(R"j({"id":1,"result":{"protocol":1,"slaves":2,"faults":true,"simulated":false,
                            "time_ns":0,"next_event":0}})j"));
}

TEST(ControlHandler, IdIsEchoedWhateverItsType) {
  Rig rig;
  EXPECT_EQ(rig.ask({{"id", "abc"}, {"cmd", "time"}})["id"], "abc");
  EXPECT_EQ(rig.ask({{"cmd", "time"}})["id"], nullptr);
  EXPECT_EQ(rig.ask({{"id", json::array({1, 2})}, {"cmd", "nope"}})["id"], json::array({1, 2}));
}

TEST(ControlHandler, NetworkShowsEverySlaveInOrderWithRegisters) {
  Rig rig;
  ASSERT_EQ(rig.bring_up(), "");
  const json net = rig.result({{"cmd", "network"}});
  ASSERT_EQ(net["slaves"].size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const json& s = net["slaves"][i];
    EXPECT_EQ(s["position"], i);
    EXPECT_EQ(s["name"], "slave");
    EXPECT_EQ(s["device"], "Generic servo");
    EXPECT_EQ(s["identity"], json::parse(R"j({"vendor_id":0,"product_code":1026,"revision":65536,"serial":0})j"));
    EXPECT_EQ(s["station_address"], 0x1001 + i);
    EXPECT_EQ(s["al_status"], 0x08);
    EXPECT_EQ(s["al_state"], "OP");
    EXPECT_EQ(s["al_error"], false);
    EXPECT_EQ(s["al_status_code"], 0);
    EXPECT_EQ(s["al_control"], 0x08);
    EXPECT_EQ(s["watchdog"]["process_data_ok"], true);
    EXPECT_EQ(s["watchdog"]["process_data_expiries"], 0);
    EXPECT_EQ(s["sync_errors"], 0);
    ASSERT_EQ(s["ports"].size(), 4u);
    EXPECT_EQ(s["ports"][0]["link"], true);
    EXPECT_EQ(s["ports"][0]["communication"], true);
    EXPECT_EQ(s["ports"][0]["rx_errors"], 0);
  }
  // The first slave's port 1 goes on to the second; the last one's is open.
  EXPECT_EQ(net["slaves"][0]["ports"][1]["link"], true);
  EXPECT_EQ(net["slaves"][1]["ports"][1]["link"], false);
  // The same registers as the master reads them.
  for (std::size_t i = 0; i < 2; ++i) {
    auto dl = rig.master.fprd_u16(rig.master.slave(i).station_address, 0x0110);
    ASSERT_TRUE(dl);
    EXPECT_EQ(net["slaves"][i]["dl_status"], *dl);
  }
  EXPECT_EQ(rig.result({{"cmd", "slave"}, {"slave", 1}}), net["slaves"][1]);
}

TEST(ControlHandler, ReadsAnyEntryWithItsTypeAndBytes) {
  Rig rig;
  EXPECT_EQ(rig.result({{"cmd", "read"}, {"slave", 0}, {"index", "0x1008"}}),
            json::parse(R"j({"index":4104,"subindex":0,"name":"Device name","type":"VISIBLE_STRING",
                            "value":"Generic servo","hex":"47656e6572696320736572766f"})j"));
  EXPECT_EQ(rig.result({{"cmd", "read"}, {"slave", 1}, {"index", 0x1018}, {"subindex", 2}}),
            json::parse(R"j({"index":4120,"subindex":2,"name":"Product code","type":"UNSIGNED32",
                            "value":1026,"hex":"02040000"})j"));
}

// ESC registers as the firmware reads them (PDI), without side effects:
// the same bytes the network view shows, the DC block at the ESC's time.
TEST(ControlHandler, ReadsRegistersAsTheFirmwareSeesThem) {
  Rig rig;
  EXPECT_EQ(rig.result({{"cmd", "register"}, {"slave", 0}, {"address", "0x0130"}}),
            json::parse(R"j({"address":304,"size":2,"value":1,"hex":"0001"})j"));  // AL status: Init
  EXPECT_EQ(rig.result({{"cmd", "register"}, {"slave", 1}, {"address", "0x0000"}, {"size", 1}})["value"],
            rig.chain[1].esc().memory()[0x0000]);  // ESC type
  const json net = rig.result({{"cmd", "network"}});
  EXPECT_EQ(rig.result({{"cmd", "register"}, {"slave", 1}, {"address", "0x0110"}})["value"],
            net["slaves"][1]["dl_status"]);
  // 4 bytes from two 16-bit reads, little-endian: 0x0130 and 0x0132 (reserved, 0).
  EXPECT_EQ(rig.result({{"cmd", "register"}, {"slave", 0}, {"address", 0x0130}, {"size", 4}})["hex"], "00000001");
  // 0x0910 (system time, 64 bit) is the ESC's time at its latest access
  // (a frame, a PDI access), not the host clock's: no frame, no change.
  const auto t0 = rig.result({{"cmd", "register"}, {"slave", 0}, {"address", "0x0910"}, {"size", 8}})["value"]
                      .get<std::uint64_t>();
  rig.clock.advance(std::chrono::microseconds(1500));
  const auto t1 = rig.result({{"cmd", "register"}, {"slave", 0}, {"address", "0x0910"}, {"size", 8}})["value"]
                      .get<std::uint64_t>();
  EXPECT_EQ(t1, t0);
  // A read does not acknowledge what the firmware would: the AL event
  // request 0x0220 is read twice with the same value.
  const json ev = rig.result({{"cmd", "register"}, {"slave", 0}, {"address", "0x0220"}, {"size", 4}});
  EXPECT_EQ(rig.result({{"cmd", "register"}, {"slave", 0}, {"address", "0x0220"}, {"size", 4}}), ev);
  // Bad input: the message names the limit.
  EXPECT_EQ(rig.ask({{"id", 1}, {"cmd", "register"}, {"slave", 0}, {"address", "0x0FFF"}, {"size", 2}}),
            json::parse(R"j({"id":1,"error":{"code":"bad_request",
                "message":"register 0x0FFF + 2 bytes goes past the registers (0x0000-0x0FFF)"}})j"));
  EXPECT_EQ(rig.ask({{"id", 2}, {"cmd", "register"}, {"slave", 0}, {"address", 0x10}, {"size", 3}}),
            json::parse(R"j({"id":2,"error":{"code":"bad_request","message":"\"size\": 3 is not 1, 2, 4 or 8 bytes"}})j"));
  EXPECT_EQ(rig.refused({{"cmd", "register"}, {"slave", 0}, {"address", "0x1000"}}), "bad_request");
  EXPECT_EQ(rig.refused({{"cmd", "register"}, {"slave", 0}}), "bad_request");
  EXPECT_EQ(rig.refused({{"cmd", "register"}, {"slave", 2}, {"address", 0}}), "unknown_slave");
  EXPECT_EQ(rig.result({{"cmd", "network"}}), rig.result({{"cmd", "network"}}));
}

TEST(ControlHandler, WritesWhatTheDeviceWouldSetItselfAndTheMasterReadsIt) {
  Rig rig;
  // 6064h is read-only to the master (an input); the device's side sets it.
  EXPECT_EQ(rig.result({{"cmd", "write"}, {"slave", 1}, {"index", "0x6064"}, {"value", -12345}}),
            json::parse(R"j({"index":24676,"subindex":0,"name":"Position actual value","type":"INTEGER32",
                            "value":-12345,"hex":"c7cfffff"})j"));
  EXPECT_EQ(rig.position(1), -12345);
  EXPECT_EQ(rig.position(0), 0);
  ASSERT_TRUE(rig.master.scan());
  ASSERT_TRUE(rig.master.configure_mailbox(1));
  ASSERT_TRUE(rig.master.request_state(1, master::AlState::PreOp));
  master::CoeClient coe(rig.master, 1);
  auto bytes = coe.upload(0x6064, 0);
  ASSERT_TRUE(bytes);
  EXPECT_EQ(*bytes, (std::vector<std::uint8_t>{0xC7, 0xCF, 0xFF, 0xFF}));
  // Raw bytes of any type.
  EXPECT_EQ(rig.result({{"cmd", "write"}, {"slave", 1}, {"index", "0x6041"}, {"value", {{"hex", "3712"}}}})["value"],
            0x1237);
}

TEST(ControlHandler, BadObjectAccessIsRefusedAndChangesNothing) {
  Rig rig;
  ASSERT_TRUE(rig.result({{"cmd", "write"}, {"slave", 0}, {"index", "0x6064"}, {"value", 77}}).is_object());
  const json before = rig.result({{"cmd", "network"}});
  EXPECT_EQ(rig.ask({{"id", 3}, {"cmd", "read"}, {"slave", 2}, {"index", "0x6064"}}),
            json::parse(R"j({"id":3,"error":{"code":"unknown_slave",
                            "message":"slave 2: no such slave (chain has 2, positions 0..1)"}})j"));
  EXPECT_EQ(rig.ask({{"id", 4}, {"cmd", "read"}, {"slave", 0}, {"index", "0x5555"}}),
            json::parse(R"j({"id":4,"error":{"code":"unknown_object","message":"no object 5555h in the dictionary"}})j"));
  EXPECT_EQ(rig.refused({{"cmd", "read"}, {"slave", 0}, {"index", "0x1018"}, {"subindex", 9}}), "unknown_subindex");
  EXPECT_EQ(rig.ask({{"id", 5}, {"cmd", "write"}, {"slave", 0}, {"index", "0x1008"}, {"value", "x"}}),
            json::parse(R"j({"id":5,"error":{"code":"read_only",
                            "message":"1008h:00h is a constant of the device (const): never written"}})j"));
  EXPECT_EQ(rig.refused({{"cmd", "write"}, {"slave", 0}, {"index", "0x6064"}, {"value", "12"}}), "bad_value");
  EXPECT_EQ(rig.refused({{"cmd", "write"}, {"slave", 0}, {"index", "0x6064"}, {"value", 1.5}}), "bad_value");
  EXPECT_EQ(rig.refused({{"cmd", "write"}, {"slave", 0}, {"index", "0x6064"}, {"value", {{"hex", "12"}}}}),
            "bad_value");
  EXPECT_EQ(rig.refused({{"cmd", "write"}, {"slave", 0}, {"index", "0x6064"}, {"value", {{"hex", "zz"}}}}),
            "bad_value");
  EXPECT_EQ(rig.refused({{"cmd", "write"}, {"slave", 0}, {"index", "0x6064"}, {"value", 2147483648LL}}),
            "out_of_range");
  EXPECT_EQ(rig.ask({{"id", 6}, {"cmd", "write"}, {"slave", 0}, {"index", "0x6040"}, {"value", 65536}}),
            json::parse(R"j({"id":6,"error":{"code":"out_of_range",
                            "message":"6040h:00h: 65536 is outside UNSIGNED16 (0..65535)"}})j"));
  EXPECT_EQ(rig.refused({{"cmd", "write"}, {"slave", 0}, {"index", "0x6040"}, {"value", -1}}), "out_of_range");
  // The dictionary's own range: 60C2h:02 is -128..63.
  EXPECT_EQ(rig.refused({{"cmd", "write"}, {"slave", 0}, {"index", "0x60C2"}, {"subindex", 2}, {"value", 64}}),
            "out_of_range");
  EXPECT_EQ(rig.result({{"cmd", "read"}, {"slave", 0}, {"index", "0x60C2"}, {"subindex", 2}})["value"], -3);
  EXPECT_EQ(rig.refused({{"cmd", "write"}, {"slave", 0}, {"index", "0x6064"}}), "bad_request");
  EXPECT_EQ(rig.refused({{"cmd", "read"}, {"slave", 0}}), "bad_request");
  EXPECT_EQ(rig.refused({{"cmd", "read"}, {"slave", 0}, {"index", "0x10000"}}), "bad_request");
  EXPECT_EQ(rig.refused({{"cmd", "read"}, {"slave", 0}, {"index", "six"}}), "bad_request");
  EXPECT_EQ(rig.refused({{"cmd", "read"}, {"slave", -1}, {"index", 1}}), "bad_request");
  EXPECT_EQ(rig.refused({{"cmd", "read"}, {"index", 1}}), "bad_request");
  EXPECT_EQ(rig.position(0), 77);
  EXPECT_EQ(rig.result({{"cmd", "network"}}), before);
}

TEST(ControlHandler, MalformedMessagesGetAnErrorLine) {
  Rig rig;
  // Keys come sorted (nlohmann::json).
  EXPECT_EQ(rig.handler->handle_line("{\"cmd\": "),
            R"j({"error":{"code":"bad_json","message":"the line is not one JSON value"},"id":null})j");
  EXPECT_EQ(rig.handler->handle_line("[1,2]"),
            R"j({"error":{"code":"bad_request","message":"a request is a JSON object with \"cmd\""},"id":null})j");
  EXPECT_EQ(rig.handler->handle_line(R"j({"id":2,"cmd":5})j"),
            R"j({"error":{"code":"bad_request","message":"\"cmd\" (a string) is needed"},"id":2})j");
  const json unknown = json::parse(rig.handler->handle_line(R"j({"id":9,"cmd":"explode"})j"));
  EXPECT_EQ(unknown["error"]["code"], "unknown_command");
  EXPECT_EQ(unknown["error"]["message"].get<std::string>().rfind("unknown command 'explode' (known: hello, network", 0),
            0u);
  EXPECT_EQ(rig.refused({{"cmd", "subscribe"}}), "not_streaming");
}

TEST(ControlHandler, ProcessDataEntriesByName) {
  Rig rig;
  const json list = rig.result({{"cmd", "pdo"}, {"slave", 0}})["entries"];
  ASSERT_FALSE(list.empty());
  EXPECT_EQ(list[0], json::parse(R"j({"pdo":5632,"pdo_name":"Outputs (CSP/CSV/CST)","direction":"rx",
                                     "name":"Controlword","index":24640,"subindex":0,"bit_length":16,"value":0})j"));
  EXPECT_EQ(rig.result({{"cmd", "pdo"}, {"slave", 1}, {"name", "Position actual value"}, {"value", 4096}}),
            json::parse(R"j({"index":24676,"subindex":0,"name":"Position actual value","type":"INTEGER32",
                            "value":4096,"hex":"00100000","pdo":6656,"direction":"tx"})j"));
  EXPECT_EQ(rig.position(1), 4096);
  EXPECT_EQ(rig.result({{"cmd", "pdo"}, {"slave", 1}, {"name", "Inputs (CSP/CSV/CST)/Statusword"}})["index"], 0x6041);
  EXPECT_EQ(rig.ask({{"id", 1}, {"cmd", "pdo"}, {"slave", 0}, {"name", "Temperature"}}),
            json::parse(R"j({"id":1,"error":{"code":"unknown_pdo_entry",
                            "message":"no process-data entry 'Temperature' in the device's PDOs"}})j"));
  EXPECT_EQ(rig.refused({{"cmd", "pdo"}, {"slave", 0}, {"name", 7}}), "bad_request");
}

TEST(ControlHandler, FaultsEngagedListedAndClearedWithEvents) {
  Rig rig;
  const json kinds = rig.result({{"cmd", "fault_kinds"}})["kinds"];
  ASSERT_EQ(kinds.size(), slave::FaultCatalogue::kinds().size());
  EXPECT_EQ(kinds[0]["name"], std::string(slave::FaultCatalogue::kinds()[0].name));
  const json engaged = rig.result({{"cmd", "fault_engage"}, {"kind", "link_cut"}, {"slave", 0}, {"port", 1}});
  ASSERT_TRUE(engaged["fault"].is_number_unsigned());
  const auto id = engaged["fault"].get<std::uint64_t>();
  EXPECT_EQ(rig.result({{"cmd", "faults"}}),
            json::parse(fmt::format(R"j({{"faults":[{{"fault":{},"kind":"link_cut","params":{{}},"slave":0,"port":1}}]}})j",
                                    id)));
  EXPECT_EQ(rig.result({{"cmd", "fault_clear"}, {"fault", id}}), json::parse(R"j({"cleared":1})j"));
  EXPECT_EQ(rig.result({{"cmd", "faults"}}), json::parse(R"j({"faults":[]})j"));
  const json ev = rig.result({{"cmd", "events"}});
  ASSERT_EQ(ev["events"].size(), 2u);
  EXPECT_EQ(ev["events"][0]["type"], "fault_engaged");
  EXPECT_EQ(ev["events"][0]["kind"], "link_cut");
  EXPECT_EQ(ev["events"][0]["fault"], id);
  EXPECT_EQ(ev["events"][0]["seq"], 0);
  EXPECT_EQ(ev["events"][1]["type"], "fault_cleared");
  EXPECT_EQ(ev["next"], 2);
  EXPECT_EQ(rig.result({{"cmd", "events"}, {"since", 1}})["events"].size(), 1u);
}

TEST(ControlHandler, BadFaultRequestsAreRefusedAndEngageNothing) {
  Rig rig;
  const json unknown = rig.ask({{"id", 1}, {"cmd", "fault_engage"}, {"kind", "meteor"}});
  EXPECT_EQ(unknown["error"]["code"], "unknown_fault");
  EXPECT_EQ(unknown["error"]["message"].get<std::string>().rfind("unknown fault kind 'meteor' (known: link_cut", 0), 0u);
  EXPECT_EQ(rig.refused({{"cmd", "fault_engage"}, {"kind", "link_cut"}, {"slave", 7}, {"port", 1}}), "unknown_slave");
  EXPECT_EQ(rig.refused({{"cmd", "fault_engage"}, {"kind", "link_cut"}, {"slave", 0}}), "fault_refused");
  EXPECT_EQ(rig.refused({{"cmd", "fault_engage"}, {"kind", "drop_frames"}, {"params", {{"count", "x"}}}}),
            "bad_request");
  EXPECT_EQ(rig.refused({{"cmd", "fault_engage"}, {"kind", "drop_frames"}, {"params", {{"bogus", 1}}}}),
            "fault_refused");
  EXPECT_EQ(rig.refused({{"cmd", "fault_engage"}}), "bad_request");
  EXPECT_EQ(rig.refused({{"cmd", "fault_clear"}, {"fault", 99}}), "unknown_fault");
  EXPECT_EQ(rig.refused({{"cmd", "fault_clear"}}), "bad_request");
  EXPECT_EQ(rig.result({{"cmd", "faults"}}), json::parse(R"j({"faults":[]})j"));
  EXPECT_EQ(rig.result({{"cmd", "events"}})["events"].size(), 0u);
}

TEST(ControlHandler, WithoutCatalogueOrSimulatedTimeThoseCommandsSaySo) {
  InProcess p;
  p.add_default(1);
  control::EventQueue events;
  control::RequestHandler handler(p.chain, p.clock, events);
  EXPECT_EQ(handler.handle({{"cmd", "faults"}})["error"]["code"], "no_faults");
  EXPECT_EQ(handler.handle({{"id", 1}, {"cmd", "step"}}),
            json::parse(R"j({"id":1,"error":{"code":"not_simulated",
                            "message":"this network runs on the wall clock: pause, step and run need simulated time"}})j"));
  EXPECT_EQ(handler.handle({{"cmd", "pause"}})["error"]["code"], "not_simulated");
  EXPECT_EQ(handler.handle({{"cmd", "time"}})["result"], json::parse(R"j({"time_ns":0,"simulated":false})j"));
}

TEST(ControlHandler, SimulatedTimePausesStepsAndRuns) {
  InProcess p;
  p.add_default(1);
  std::vector<Nanoseconds> cycles;
  control::SimulatedRun sim(p.clock, p.chain, std::chrono::milliseconds(1),
                            [&](Nanoseconds now) { cycles.push_back(now); });
  control::EventQueue events;
  control::RequestHandler handler(p.chain, p.clock, events, nullptr, &sim);
  EXPECT_EQ(handler.handle({{"cmd", "pause"}})["result"],
            json::parse(R"j({"time_ns":0,"simulated":true,"paused":true,"cycles":0,"period_ns":1000000})j"));
  EXPECT_FALSE(sim.tick());
  EXPECT_EQ(handler.handle({{"cmd", "step"}, {"cycles", 5}})["result"],
            json::parse(R"j({"time_ns":5000000,"simulated":true,"paused":true,"cycles":5,"period_ns":1000000})j"));
  EXPECT_EQ(cycles, (std::vector<Nanoseconds>{std::chrono::milliseconds(1), std::chrono::milliseconds(2),
                                              std::chrono::milliseconds(3), std::chrono::milliseconds(4),
                                              std::chrono::milliseconds(5)}));
  EXPECT_EQ(handler.handle({{"cmd", "step"}, {"cycles", 10'000'001}})["error"]["code"], "bad_request");
  EXPECT_EQ(sim.cycles(), 5u);
  EXPECT_EQ(handler.handle({{"cmd", "run"}})["result"]["paused"], false);
  EXPECT_TRUE(sim.tick());
  EXPECT_EQ(p.clock.now(), std::chrono::milliseconds(6));
}

}  // namespace
}  // namespace ecat::test
