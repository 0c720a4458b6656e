// The control interface on a socket (issue 26 item 1, docs/control.md): JSON
// lines over a Unix socket (mode 0600) or TCP (loopback unless an address
// is named, as ecat-slave --udp), for ecat-slave and for in-process users
// alike. Non-blocking and thread-free: the owner's loop calls service(now)
// and it does its work on a 10 ms tick - accept, read, answer through the
// RequestHandler, sample the chain for events (EventWatcher), stream them to
// subscribed clients - so between ticks it costs one comparison and nothing
// runs on the frame path.
//
// Besides the handler's commands a stream client may send
// {"cmd":"subscribe","since":N} (events then arrive as {"event":{...}} lines,
// from N or from now) and {"cmd":"unsubscribe"}.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <poll.h>

#include "common/clock.hpp"
#include "common/expected.hpp"
#include "control/event_watcher.hpp"
#include "control/request_handler.hpp"

namespace ecat::control {

// Where --control listens: "PORT" (127.0.0.1), "ADDR:PORT" or
// "[V6ADDR]:PORT" (TCP), anything else a Unix socket path.
struct ControlEndpoint {
  bool tcp = false;
  std::string path;  // Unix socket
  std::string host;  // TCP address (numeric)
  std::uint16_t port = 0;
};
Expected<ControlEndpoint, std::string> parse_control_endpoint(std::string_view spec);

class ControlServer {
 public:
  static constexpr Nanoseconds kTick = std::chrono::milliseconds(10);
  static constexpr std::size_t kMaxClients = 16;
  static constexpr std::size_t kMaxLineBytes = 1 << 20;      // a longer request is refused
  static constexpr std::size_t kMaxPendingBytes = 16 << 20;  // a client that reads no replies is dropped

  // Listens on `spec` (parse_control_endpoint). A Unix socket path that
  // exists as a socket is replaced (a stale one of an earlier run); any
  // other file there is an error.
  static Expected<std::unique_ptr<ControlServer>, std::string> open(std::string_view spec, RequestHandler& handler);
  ~ControlServer();
  ControlServer(const ControlServer&) = delete;
  ControlServer& operator=(const ControlServer&) = delete;

  // The work of a tick when one is due (see above); cheap otherwise.
  void service(Nanoseconds now);
  // How long the owner may sleep before service() is due again.
  Nanoseconds until_due(Nanoseconds now) const noexcept { return now >= next_ ? Nanoseconds{0} : next_ - now; }

  // "unix PATH" or "tcp ADDR:PORT" (the port chosen when PORT was 0).
  const std::string& address() const noexcept { return address_; }
  bool loopback_only() const noexcept { return loopback_; }
  std::size_t clients() const noexcept { return clients_.size(); }

 private:
  struct Client {
    int fd = -1;
    std::string in;
    std::string out;
    bool discarding = false;  // skipping the rest of a too long line
    bool subscribed = false;
    std::uint64_t cursor = 0;  // next event to stream
  };
  ControlServer(int fd, RequestHandler& handler);

  void accept_clients();
  // False when the client has gone (closed, error, too far behind).
  bool read_client(Client& c);
  void answer(Client& c, std::string_view line);
  void stream_events(Client& c);
  bool flush(Client& c);

  int listen_fd_ = -1;
  RequestHandler& handler_;
  EventWatcher watcher_;
  std::vector<Client> clients_;
  std::vector<pollfd> fds_;
  std::string unix_path_;  // unlinked when the server closes
  std::string address_;
  bool loopback_ = true;
  Nanoseconds next_{Nanoseconds::min()};
};

}  // namespace ecat::control
