// The control interface on a socket (control::ControlServer): a Unix socket
// created 0600, requests answered line by line on the 10 ms tick, events
// streamed to a subscriber, and the bad cases - a too long line, a client
// that disconnects mid-stream, a path that is not a socket - answered or
// survived while the chain keeps running.
#include <gtest/gtest.h>

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "control/control_server.hpp"
#include "slave/fault_catalogue.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

using nlohmann::json;
using control::ControlServer;

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / (name + "-" + std::to_string(::getpid()))).string();
}

int connect_unix(const std::string& path) {
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::snprintf(addr.sun_path, sizeof(addr.sun_path), "%s", path.c_str());
  EXPECT_EQ(::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)), 0);
  return fd;
}

void send_text(int fd, const std::string& text) {
  ASSERT_EQ(::send(fd, text.data(), text.size(), MSG_NOSIGNAL), static_cast<ssize_t>(text.size()));
}

// What arrived, without waiting (the server answered in service()).
std::string drain(int fd) {
  std::string out;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::recv(fd, buf, sizeof(buf), MSG_DONTWAIT);
    if (n <= 0) break;
    out.append(buf, static_cast<std::size_t>(n));
  }
  return out;
}

struct Rig : InProcess {
  control::EventQueue events;
  slave::FaultCatalogue faults{chain};
  control::RequestHandler handler{chain, clock, events, &faults};
  std::string path = temp_path("ecat-control-test");
  std::unique_ptr<ControlServer> server;

  Rig() {
    add_default(1);
    auto s = ControlServer::open(path, handler);
    if (!s) throw std::runtime_error(s.error());
    server = std::move(*s);
  }
  // One tick of the server, 10 ms of simulated time later.
  void tick() {
    advance(ControlServer::kTick);
    server->service(clock.now());
  }
};

TEST(ControlEndpoint, PortAloneIsLoopbackTcpAddressPortIsTcpAnythingElseIsAPath) {
  auto a = control::parse_control_endpoint("5000");
  ASSERT_TRUE(a);
  EXPECT_TRUE(a->tcp);
  EXPECT_EQ(a->host, "127.0.0.1");
  EXPECT_EQ(a->port, 5000);
  auto b = control::parse_control_endpoint("[::1]:7");
  ASSERT_TRUE(b);
  EXPECT_EQ(b->host, "::1");
  EXPECT_EQ(b->port, 7);
  auto c = control::parse_control_endpoint("/run/ecat/ctl.sock");
  ASSERT_TRUE(c);
  EXPECT_FALSE(c->tcp);
  EXPECT_EQ(c->path, "/run/ecat/ctl.sock");
  EXPECT_FALSE(control::parse_control_endpoint("70000"));
  EXPECT_FALSE(control::parse_control_endpoint(""));
}

TEST(ControlServer, UnixSocketIsOwnerOnlyAndRemovedAtClose) {
  Rig rig;
  struct stat st {};
  ASSERT_EQ(::stat(rig.path.c_str(), &st), 0);
  EXPECT_TRUE(S_ISSOCK(st.st_mode));
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  EXPECT_EQ(rig.server->address(), "unix " + rig.path);
  rig.server.reset();
  EXPECT_FALSE(std::filesystem::exists(rig.path));
}

TEST(ControlServer, RefusesAPathThatIsNotASocket) {
  InProcess p;
  p.add_default(1);
  control::EventQueue events;
  control::RequestHandler handler(p.chain, p.clock, events);
  const std::string path = temp_path("ecat-control-file");
  std::ofstream(path) << "keep me";
  auto s = ControlServer::open(path, handler);
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error(), "--control " + path + ": exists and is not a socket");
  EXPECT_TRUE(std::filesystem::exists(path));
  std::filesystem::remove(path);
}

TEST(ControlServer, AnswersLinesOnTheTickAndKeepsPartialOnes) {
  Rig rig;
  const int fd = connect_unix(rig.path);
  rig.tick();  // accepted
  send_text(fd, "{\"id\":1,\"cmd\":\"hello\"}\n{\"id\":2,\"cmd\":\"rea");
  EXPECT_EQ(drain(fd), "");  // nothing before the tick
  rig.tick();
  const std::string first = drain(fd);
  ASSERT_EQ(first.back(), '\n');
  EXPECT_EQ(json::parse(first)["result"]["protocol"], 1);
  send_text(fd, "d\",\"slave\":0,\"index\":\"0x1018\",\"subindex\":2}\r\n\n");
  rig.tick();
  // Keys come sorted (nlohmann::json); one reply per line.
  EXPECT_EQ(drain(fd),
            R"j({"id":2,"result":{"hex":"02040000","index":4120,"name":"Product code","subindex":2,"type":"UNSIGNED32","value":1026}})j"
            "\n");
  send_text(fd, "not json\n");
  rig.tick();
  EXPECT_EQ(drain(fd), R"j({"error":{"code":"bad_json","message":"the line is not one JSON value"},"id":null})j" "\n");
  ::close(fd);
}

TEST(ControlServer, TooLongLineIsRefusedAndTheNextOneAnswered) {
  Rig rig;
  const int fd = connect_unix(rig.path);
  rig.tick();
  const std::string huge(ControlServer::kMaxLineBytes + 10, 'x');
  std::string got;
  // Send in pieces, ticking, so neither side's buffer fills.
  for (std::size_t at = 0; at < huge.size(); at += 65536) {
    send_text(fd, huge.substr(at, 65536));
    rig.tick();
    got += drain(fd);
  }
  send_text(fd, "tail\n{\"id\":5,\"cmd\":\"time\"}\n");
  rig.tick();
  got += drain(fd);
  const auto nl = got.find('\n');
  ASSERT_NE(nl, std::string::npos);
  EXPECT_EQ(json::parse(got.substr(0, nl))["error"]["code"], "line_too_long");
  EXPECT_EQ(json::parse(got.substr(nl + 1))["id"], 5);
  ::close(fd);
}

TEST(ControlServer, StreamsEventsToASubscriberAndSurvivesItsDisconnect) {
  Rig rig;
  const int fd = connect_unix(rig.path);
  rig.tick();
  send_text(fd, "{\"id\":1,\"cmd\":\"subscribe\"}\n");
  rig.tick();
  EXPECT_EQ(drain(fd), R"j({"id":1,"result":{"next":0,"subscribed":true}})j" "\n");
  // The master brings the slave to PreOp: AL control and AL status change.
  ASSERT_TRUE(rig.master.scan());
  ASSERT_TRUE(rig.master.configure_mailbox(0));
  ASSERT_TRUE(rig.master.request_state(0, master::AlState::PreOp));
  rig.tick();
  const std::string lines = drain(fd);
  const auto nl = lines.find('\n');
  ASSERT_NE(nl, std::string::npos);
  const json control_event = json::parse(lines.substr(0, nl))["event"];
  EXPECT_EQ(control_event["type"], "al_control");
  EXPECT_EQ(control_event["requested"], "PREOP");
  const json state_event = json::parse(lines.substr(nl + 1, lines.find('\n', nl + 1) - nl - 1))["event"];
  EXPECT_EQ(state_event["type"], "al_state");
  EXPECT_EQ(state_event["from"], "INIT");
  EXPECT_EQ(state_event["to"], "PREOP");
  EXPECT_EQ(state_event["slave"], 0);
  // Gone mid-stream with events pending: the server drops it, nothing else.
  ASSERT_TRUE(rig.faults.engage({"link_cut", 0, 0, {}}));
  ::close(fd);
  rig.tick();
  rig.tick();
  EXPECT_EQ(rig.server->clients(), 0u);
  const int again = connect_unix(rig.path);
  rig.tick();
  send_text(again, "{\"id\":2,\"cmd\":\"slave\",\"slave\":0}\n");
  rig.tick();
  EXPECT_EQ(json::parse(drain(again))["result"]["al_state"], "PREOP");
  ::close(again);
}

TEST(ControlServer, TcpOnLoopbackByDefault) {
  InProcess p;
  p.add_default(1);
  control::EventQueue events;
  control::RequestHandler handler(p.chain, p.clock, events);
  auto s = ControlServer::open("127.0.0.1:0", handler);
  ASSERT_TRUE(s) << s.error();
  EXPECT_TRUE((*s)->loopback_only());
  EXPECT_EQ((*s)->address().rfind("tcp 127.0.0.1:", 0), 0u);
}

}  // namespace
}  // namespace ecat::test
