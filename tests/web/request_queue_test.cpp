// The hand-off between HTTP threads and the live loop (web/request_queue.hpp):
// a request waits until the loop serves it, gets the RequestHandler's exact
// reply, and is refused (not hung) when the queue is full or closed.
#include <gtest/gtest.h>

#include <future>
#include <thread>

#include <nlohmann/json.hpp>

#include "control/request_handler.hpp"
#include "tests/slave/inprocess_fixture.hpp"
#include "web/request_queue.hpp"

namespace ecat::test {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;

struct QueueRig : InProcess {
  control::EventQueue events;
  control::RequestHandler handler{chain, clock, events};
  web::RequestQueue queue;
  QueueRig() { add_default(2); }
};

TEST(WebRequestQueue, TheCallerWaitsForTheLoopAndGetsTheHandlersReply) {
  QueueRig rig;
  auto reply = std::async(std::launch::async, [&] { return rig.queue.call(R"({"id":3,"cmd":"hello"})", 10s); });
  // Served on this thread (the loop's), until the caller has its answer.
  std::size_t served = 0;
  while (reply.wait_for(1ms) != std::future_status::ready) served += rig.queue.serve(rig.handler);
  EXPECT_EQ(served, 1u);
  const auto text = reply.get();
  ASSERT_TRUE(text);
  EXPECT_EQ(json::parse(*text), json::parse(R"j({"id":3,"result":{"protocol":1,"slaves":2,"faults":false,
                                              "simulated":false,"time_ns":0,"next_event":0}})j"));
}

TEST(WebRequestQueue, BadJsonIsTheHandlersError) {
  QueueRig rig;
  auto reply = std::async(std::launch::async, [&] { return rig.queue.call("{nope", 10s); });
  while (reply.wait_for(1ms) != std::future_status::ready) rig.queue.serve(rig.handler);
  const auto text = reply.get();
  ASSERT_TRUE(text);
  EXPECT_EQ(json::parse(*text)["error"]["code"], "bad_json");
}

TEST(WebRequestQueue, NobodyServingTimesOutAndAFullQueueRefuses) {
  QueueRig rig;
  // Each call times out but its request stays queued (served later, the answer dropped).
  for (std::size_t i = 0; i < web::RequestQueue::kMaxWaiting; ++i) {
    EXPECT_EQ(rig.queue.call(R"({"cmd":"time"})", 1ms), std::nullopt);
  }
  // Full: refused without waiting for the long timeout.
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(rig.queue.call(R"({"cmd":"time"})", 60s), std::nullopt);
  EXPECT_LT(std::chrono::steady_clock::now() - start, 30s);
  EXPECT_EQ(rig.queue.serve(rig.handler), web::RequestQueue::kMaxWaiting);
  EXPECT_EQ(rig.queue.serve(rig.handler), 0u);
}

TEST(WebRequestQueue, ClosingRefusesWhatWaitsAndWhatComes) {
  QueueRig rig;
  auto reply = std::async(std::launch::async, [&] { return rig.queue.call(R"({"cmd":"time"})", 10s); });
  std::this_thread::sleep_for(5ms);  // not needed for correctness: either order ends with nothing
  rig.queue.close();
  EXPECT_EQ(reply.get(), std::nullopt);
  EXPECT_EQ(rig.queue.call(R"({"cmd":"time"})", 10s), std::nullopt);
}

}  // namespace
}  // namespace ecat::test
