// ecat-slave --http's server (web/web_server.hpp) on a real socket: requests
// answered only when the loop services it, the handler's exact replies, clear
// JSON errors, 404 and refused paths, loopback by default, and the event
// stream with its snapshot and the control interface's events.
#include <gtest/gtest.h>

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <future>
#include <mutex>
#include <thread>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "control/request_handler.hpp"
#include "slave/fault_catalogue.hpp"
#include "tests/slave/inprocess_fixture.hpp"
#include "web/web_server.hpp"

namespace ecat::test {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;

struct WebRig : InProcess {
  control::EventQueue events;
  slave::FaultCatalogue faults{chain};
  control::RequestHandler handler{chain, clock, events, &faults};
  std::filesystem::path www = std::filesystem::temp_directory_path() / ("ecat-web-test-" + std::to_string(::getpid()));
  std::unique_ptr<web::WebServer> server;
  Nanoseconds now{0};

  WebRig() {
    add_default(2);
    std::filesystem::create_directories(www);
    std::ofstream(www / "index.html") << "<!doctype html><title>ecat</title>";
    auto s = web::WebServer::open({"0", www.string(), true}, handler);
    EXPECT_TRUE(s) << (s ? "" : s.error());
    if (s) server = std::move(*s);
  }
  ~WebRig() {
    server.reset();
    std::filesystem::remove_all(www);
  }
  httplib::Client client() {
    httplib::Client c("127.0.0.1", server->port());
    c.set_read_timeout(20, 0);
    return c;
  }
  void service() {
    now += web::WebServer::kTick;
    server->service(now);
  }
  // Runs `call` on another thread while this one is the live loop.
  template <typename F>
  auto serve_while(F call) {
    auto f = std::async(std::launch::async, call);
    const auto deadline = std::chrono::steady_clock::now() + 20s;
    while (f.wait_for(1ms) != std::future_status::ready && std::chrono::steady_clock::now() < deadline) service();
    return f.get();
  }
  httplib::Result post(std::string body, std::string type = "application/json") {
    return serve_while([&] { return client().Post("/api", body, type); });
  }
};

TEST(WebServer, ListensOnLoopbackByDefault) {
  WebRig rig;
  ASSERT_TRUE(rig.server);
  EXPECT_TRUE(rig.server->loopback_only());
  EXPECT_EQ(rig.server->url(), "http://127.0.0.1:" + std::to_string(rig.server->port()) + "/");
}

TEST(WebServer, ANamedAddressIsNotLoopbackAndAPathIsRefused) {
  WebRig rig;
  auto any = web::WebServer::open({"0.0.0.0:0", rig.www.string(), true}, rig.handler);
  ASSERT_TRUE(any) << any.error();
  EXPECT_FALSE((*any)->loopback_only());
  auto path = web::WebServer::open({"/tmp/x.sock", rig.www.string(), true}, rig.handler);
  ASSERT_FALSE(path);
  EXPECT_EQ(path.error(), "--http /tmp/x.sock: expected PORT or ADDR:PORT");
}

TEST(WebServer, ApiAnswersOnlyWhenTheLoopServes) {
  WebRig rig;
  auto pending = std::async(std::launch::async, [&] { return rig.client().Post("/api", R"({"cmd":"time"})", "application/json"); });
  EXPECT_EQ(pending.wait_for(100ms), std::future_status::timeout);  // nobody services: no answer
  while (pending.wait_for(1ms) != std::future_status::ready) rig.service();
  auto r = pending.get();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_EQ(json::parse(r->body), json::parse(R"j({"id":null,"result":{"simulated":false,"time_ns":0}})j"));
}

TEST(WebServer, ApiRepliesAreTheHandlersOwn) {
  WebRig rig;
  auto r = rig.post(R"({"id":9,"cmd":"hello"})");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_EQ(r->get_header_value("Content-Type"), "application/json");
  EXPECT_EQ(json::parse(r->body), json::parse(R"j({"id":9,"result":{"protocol":1,"slaves":2,"faults":true,
                                                "simulated":false,"time_ns":0,"next_event":0}})j"));
}

TEST(WebServer, BadRequestsGetAClearJsonError) {
  WebRig rig;
  auto bad = rig.post("{not json");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400);
  EXPECT_EQ(json::parse(bad->body)["error"]["code"], "bad_json");
  auto unknown = rig.post(R"({"cmd":"read","slave":5,"index":"0x6041"})");
  ASSERT_TRUE(unknown);
  EXPECT_EQ(unknown->status, 400);
  EXPECT_EQ(json::parse(unknown->body),
            json::parse(R"j({"id":null,"error":{"code":"unknown_slave",
                            "message":"slave 5: no such slave (chain has 2, positions 0..1)"}})j"));
  auto text = rig.post(R"({"cmd":"hello"})", "text/plain");
  ASSERT_TRUE(text);
  EXPECT_EQ(text->status, 415);
  EXPECT_EQ(json::parse(text->body),
            json::parse(R"j({"error":{"code":"bad_request",
                  "message":"POST /api takes one JSON request with Content-Type: application/json"}})j"));
  auto stream_only = rig.post(R"({"cmd":"subscribe"})");
  ASSERT_TRUE(stream_only);
  EXPECT_EQ(json::parse(stream_only->body)["error"]["code"], "not_streaming");
}

TEST(WebServer, FilesAreServedMissingOnesAre404AndTraversalIsRefused) {
  WebRig rig;
  auto c = rig.client();
  auto index = c.Get("/");
  ASSERT_TRUE(index);
  EXPECT_EQ(index->status, 200);
  EXPECT_EQ(index->body, "<!doctype html><title>ecat</title>");
  EXPECT_EQ(index->get_header_value("Content-Type"), "text/html; charset=utf-8");
  auto missing = c.Get("/nope.js");
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->status, 404);
  for (const char* bad : {"/../web-test-secret", "/%2e%2e/web-test-secret", "/.hidden"}) {
    auto r = c.Get(bad);
    ASSERT_TRUE(r) << bad;
    EXPECT_EQ(r->status, 403) << bad;
  }
}

TEST(WebServer, EventsStreamASnapshotAndTheControlInterfacesEvents) {
  WebRig rig;
  ASSERT_EQ(rig.bring_up(), "");
  std::mutex mutex;
  std::string received;
  std::atomic<bool> stop{false};
  auto reader = std::async(std::launch::async, [&] {
    auto c = rig.client();
    return c.Get("/events", [&](const char* data, std::size_t n) {
      const std::lock_guard lock(mutex);
      received.append(data, n);
      return !stop.load();
    });
  });
  auto seen = [&](std::string_view what) {
    const std::lock_guard lock(mutex);
    return received.find(what) != std::string::npos;
  };
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  while (!seen("event: snapshot\ndata: ") && std::chrono::steady_clock::now() < deadline) {
    rig.service();
    std::this_thread::sleep_for(1ms);
  }
  ASSERT_TRUE(seen("event: snapshot\ndata: "));
  EXPECT_EQ(rig.server->streams(), 1u);
  {
    const std::lock_guard lock(mutex);
    const std::size_t start = received.find("data: ") + 6;
    const json snap = json::parse(received.substr(start, received.find('\n', start) - start));
    EXPECT_EQ(snap["network"]["slaves"].size(), 2u);
    EXPECT_EQ(snap["network"]["slaves"][1]["al_state"], "OP");
    EXPECT_EQ(snap["drives"].size(), 2u);
    EXPECT_EQ(snap["drives"][0]["slave"], 0);
    EXPECT_TRUE(snap["drives"][0]["statusword"].is_number());
    EXPECT_FALSE(snap.contains("pdo"));  // the page asks for its slave's own
    EXPECT_EQ(snap["faults"], json::array());
  }
  auto engaged = rig.post(R"({"cmd":"fault_engage","kind":"link_cut","slave":0,"port":1})");
  ASSERT_TRUE(engaged);
  EXPECT_EQ(engaged->status, 200);
  const auto engaged_id = json::parse(engaged->body)["result"]["fault"].get<std::uint64_t>();
  while (!seen(R"("type":"fault_engaged")") && std::chrono::steady_clock::now() < deadline) {
    rig.service();
    std::this_thread::sleep_for(1ms);
  }
  {
    const std::lock_guard lock(mutex);
    const std::size_t at = received.find(R"("type":"fault_engaged")");
    ASSERT_NE(at, std::string::npos);
    const std::size_t start = received.rfind("event: event\ndata: ", at) + 19;
    json e = json::parse(received.substr(start, received.find('\n', start) - start));
    e.erase("seq");
    e.erase("time_ns");
    EXPECT_EQ(e, json::parse(R"j({"fault":)j" + std::to_string(engaged_id) +
                             R"j(,"kind":"link_cut","params":{},"port":1,"slave":0,"type":"fault_engaged"})j"));
  }
  stop = true;
  while (reader.wait_for(1ms) != std::future_status::ready) rig.service();
}

}  // namespace
}  // namespace ecat::test
