// ecat-slave --http (issue 27, docs/webview.md): the browser's view of the
// network, on the control interface - POST /api takes one request of
// docs/control.md and returns the RequestHandler's reply, GET /events streams
// its events plus a snapshot of the network and the process data (5 Hz)
// as server-sent events, GET / and the files of share/ecatslave/www.
//
// cpp-httplib's threads parse HTTP and wait; they never touch the chain.
// Requests go through a RequestQueue and events and snapshots through
// EventStreams, both served by service(now) on the live loop's idle path,
// on a 10 ms tick like ControlServer: between ticks it is one comparison,
// and with no page connected a tick is the queue's check.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "common/clock.hpp"
#include "common/expected.hpp"

namespace ecat::control {
class RequestHandler;
}

namespace ecat::web {

struct WebOptions {
  std::string listen;    // "PORT" (127.0.0.1) or "ADDR:PORT" / "[V6ADDR]:PORT"
  std::string www_dir;   // the page's files
  bool sample_events = true;  // false when a ControlServer samples the chain already
};

class WebServer {
 public:
  static constexpr Nanoseconds kTick = std::chrono::milliseconds(10);
  static constexpr Nanoseconds kSnapshotPeriod = std::chrono::milliseconds(200);
  static constexpr std::size_t kMaxBodyBytes = 1 << 20;

  static Expected<std::unique_ptr<WebServer>, std::string> open(const WebOptions& options,
                                                                control::RequestHandler& handler);
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  void service(Nanoseconds now) {
    if (now < next_) return;
    tick(now);
  }
  Nanoseconds until_due(Nanoseconds now) const noexcept { return now >= next_ ? Nanoseconds{0} : next_ - now; }

  // "http://ADDR:PORT/" (the port chosen when PORT was 0).
  const std::string& url() const noexcept;
  std::uint16_t port() const noexcept;
  bool loopback_only() const noexcept;
  // Pages connected to /events.
  std::size_t streams() const;

 private:
  struct Impl;
  explicit WebServer(std::unique_ptr<Impl> impl);
  void tick(Nanoseconds now);

  std::unique_ptr<Impl> impl_;
  Nanoseconds next_{Nanoseconds::min()};
};

}  // namespace ecat::web
