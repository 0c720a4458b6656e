// bench_cycle's ecat-slave --http (issue 27 item 6): a web server on a
// chain with its handler, and optionally one page reading GET /events on a
// thread of its own, as a browser tab would.
#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <string>
#include <thread>

#include <httplib.h>

#include "control/request_handler.hpp"
#include "slave/fault_catalogue.hpp"
#include "web/web_server.hpp"

namespace ecat::bench {

struct HttpPage {
  ManualClock clock;
  control::EventQueue events;
  slave::FaultCatalogue faults;
  control::RequestHandler handler;
  std::unique_ptr<web::WebServer> server;
  std::unique_ptr<httplib::Client> client;
  std::atomic<bool> stop{false};
  std::atomic<std::size_t> received{0};
  std::thread reader;
  std::string error;

  HttpPage(slave::Chain& chain, bool page) : faults(chain), handler(chain, clock, events, &faults) {
    auto s = web::WebServer::open({"0", "/nonexistent", true}, handler);
    if (!s) {
      error = s.error();
      return;
    }
    server = std::move(*s);
    if (!page) return;
    client = std::make_unique<httplib::Client>("127.0.0.1", server->port());
    reader = std::thread([this] {
      client->Get("/events", [this](const char*, std::size_t n) {
        received += n;
        return !stop.load();
      });
    });
  }
  ~HttpPage() {
    stop = true;
    server.reset();  // closes the stream: the reader's Get returns
    if (reader.joinable()) reader.join();
  }
  // Runs `cycle` until the page's stream is connected and has data (not
  // measured); returns how many cycles that took (it depends on the threads'
  // timing: a count of instructions over the whole run must subtract them).
  template <typename F>
  std::size_t wait_connected(F cycle) {
    if (!client) return 0;
    std::size_t cycles = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (received.load() == 0 && std::chrono::steady_clock::now() < deadline) {
      cycle();
      ++cycles;
      std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
    return cycles;
  }
  std::size_t bytes() const { return received.load(); }
};

}  // namespace ecat::bench
