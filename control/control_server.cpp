#include "control/control_server.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <charconv>
#include <cstring>

#include <fmt/format.h>

#include "common/unix_listener.hpp"

#include "control/control_error.hpp"

namespace ecat::control {
namespace {

using nlohmann::json;

// The Unix socket is owner-only (common/unix_listener.hpp): the control
// interface reads and writes any object of any slave.
constexpr int kListenBacklog = kUnixListenBacklog;
constexpr std::size_t kReadChunk = 64 * 1024;
constexpr std::size_t kReadPerTick = 1 << 20;
constexpr std::size_t kEventsPerTick = 1000;

std::string errno_text() { return std::strerror(errno); }

bool set_nonblocking(int fd) {
  const int flags = ::fcntl(fd, F_GETFL, 0);
  return flags >= 0 && ::fcntl(fd, F_SETFL, flags | O_NONBLOCK) == 0 && ::fcntl(fd, F_SETFD, FD_CLOEXEC) == 0;
}

std::optional<std::uint16_t> parse_port(std::string_view s) {
  unsigned v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc{} || end != s.data() + s.size() || v > 0xFFFF) return std::nullopt;
  return static_cast<std::uint16_t>(v);
}

bool all_digits(std::string_view s) { return !s.empty() && s.find_first_not_of("0123456789") == std::string_view::npos; }

Expected<int, std::string> listen_unix(const std::string& path) {
  return listen_unix_owner_only(path, "--control");
}

Expected<int, std::string> listen_tcp(const ControlEndpoint& ep, std::string& address, bool& loopback) {
  sockaddr_storage storage{};
  socklen_t len = 0;
  int family = AF_INET;
  if (auto* v4 = reinterpret_cast<sockaddr_in*>(&storage); ::inet_pton(AF_INET, ep.host.c_str(), &v4->sin_addr) == 1) {
    v4->sin_family = AF_INET;
    v4->sin_port = htons(ep.port);
    len = sizeof(sockaddr_in);
    loopback = (ntohl(v4->sin_addr.s_addr) >> 24) == 127;
  } else if (auto* v6 = reinterpret_cast<sockaddr_in6*>(&storage);
             ::inet_pton(AF_INET6, ep.host.c_str(), &v6->sin6_addr) == 1) {
    v6->sin6_family = AF_INET6;
    v6->sin6_port = htons(ep.port);
    len = sizeof(sockaddr_in6);
    family = AF_INET6;
    loopback = IN6_IS_ADDR_LOOPBACK(&v6->sin6_addr);
  } else {
    return fail(fmt::format("--control {}: not a numeric IPv4 or IPv6 address", ep.host));
  }
  const int fd = ::socket(family, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return fail(fmt::format("--control: socket: {}", errno_text()));
  const int one = 1;
  ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
  if (::bind(fd, reinterpret_cast<const sockaddr*>(&storage), len) != 0 || ::listen(fd, kListenBacklog) != 0 ||
      !set_nonblocking(fd)) {
    const std::string why = errno_text();
    ::close(fd);
    return fail(fmt::format("--control {}:{}: {}", ep.host, ep.port, why));
  }
  sockaddr_storage bound{};
  socklen_t blen = sizeof(bound);
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &blen);
  const std::uint16_t port = family == AF_INET ? ntohs(reinterpret_cast<sockaddr_in*>(&bound)->sin_port)
                                               : ntohs(reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port);
  address = family == AF_INET ? fmt::format("tcp {}:{}", ep.host, port) : fmt::format("tcp [{}]:{}", ep.host, port);
  return fd;
}

json error_reply(const json& id, std::string_view code, std::string message) {
  return json{{"id", id}, {"error", {{"code", code}, {"message", std::move(message)}}}};
}

}  // namespace

Expected<ControlEndpoint, std::string> parse_control_endpoint(std::string_view spec) {
  ControlEndpoint ep;
  if (all_digits(spec)) {
    auto port = parse_port(spec);
    if (!port) return fail(fmt::format("--control {}: a port 0..65535 is needed", spec));
    ep.tcp = true;
    ep.host = "127.0.0.1";
    ep.port = *port;
    return ep;
  }
  const std::size_t colon = spec.rfind(':');
  if (colon != std::string_view::npos && spec.find('/') == std::string_view::npos && all_digits(spec.substr(colon + 1))) {
    std::string_view host = spec.substr(0, colon);
    if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
    auto port = parse_port(spec.substr(colon + 1));
    if (!port || host.empty()) return fail(fmt::format("--control {}: ADDR:PORT with a port 0..65535 is needed", spec));
    ep.tcp = true;
    ep.host = std::string(host);
    ep.port = *port;
    return ep;
  }
  if (spec.empty()) return fail(std::string("--control: a socket path or [ADDR:]PORT is needed"));
  ep.path = std::string(spec);
  return ep;
}

Expected<std::unique_ptr<ControlServer>, std::string> ControlServer::open(std::string_view spec,
                                                                          RequestHandler& handler) {
  auto ep = parse_control_endpoint(spec);
  if (!ep) return fail(ep.error());
  std::string address;
  bool loopback = true;
  auto fd = ep->tcp ? listen_tcp(*ep, address, loopback) : listen_unix(ep->path);
  if (!fd) return fail(fd.error());
  std::unique_ptr<ControlServer> server(new ControlServer(*fd, handler));
  if (ep->tcp) {
    server->address_ = address;
    server->loopback_ = loopback;
  } else {
    server->unix_path_ = ep->path;
    server->address_ = "unix " + ep->path;
  }
  return server;
}

ControlServer::ControlServer(int fd, RequestHandler& handler)
    : listen_fd_(fd), handler_(handler), watcher_(handler.chain()) {}

ControlServer::~ControlServer() {
  for (Client& c : clients_) ::close(c.fd);
  ::close(listen_fd_);
  if (!unix_path_.empty()) ::unlink(unix_path_.c_str());
}

void ControlServer::service(Nanoseconds now) {
  if (now < next_) return;
  next_ = now + kTick;
  watcher_.sample(now, handler_.events());
  fds_.clear();
  fds_.push_back({listen_fd_, POLLIN, 0});
  for (const Client& c : clients_) {
    fds_.push_back({c.fd, static_cast<short>(POLLIN | (c.out.empty() ? 0 : POLLOUT)), 0});
  }
  if (::poll(fds_.data(), fds_.size(), 0) < 0) return;
  // Clients first (fds_[1..] are in clients_ order), then new ones.
  std::vector<Client> kept;
  kept.reserve(clients_.size());
  for (std::size_t i = 0; i < clients_.size(); ++i) {
    Client& c = clients_[i];
    const short ev = fds_[i + 1].revents;
    bool alive = (ev & (POLLERR | POLLNVAL)) == 0;
    if (alive && (ev & (POLLIN | POLLHUP)) != 0) alive = read_client(c);
    if (alive && c.subscribed) stream_events(c);
    if (alive) alive = flush(c);
    if (alive) {
      kept.push_back(std::move(c));
    } else {
      ::close(c.fd);  // a client gone mid-stream changes nothing else
    }
  }
  clients_ = std::move(kept);
  if ((fds_[0].revents & POLLIN) != 0) accept_clients();
}

void ControlServer::accept_clients() {
  for (;;) {
    const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) return;
    if (clients_.size() >= kMaxClients) {
      const std::string line =
          error_reply(nullptr, error_code::kBadRequest,
                      fmt::format("too many control clients (at most {})", kMaxClients))
              .dump() +
          "\n";
      (void)::send(fd, line.data(), line.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
      ::close(fd);
      continue;
    }
    Client c;
    c.fd = fd;
    clients_.push_back(std::move(c));
  }
}

bool ControlServer::read_client(Client& c) {
  std::array<char, kReadChunk> buf;
  std::size_t total = 0;
  while (total < kReadPerTick) {
    const ssize_t n = ::recv(c.fd, buf.data(), buf.size(), MSG_DONTWAIT);
    if (n == 0) return false;  // closed
    if (n < 0) return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR;
    total += static_cast<std::size_t>(n);
    std::string_view data(buf.data(), static_cast<std::size_t>(n));
    while (!data.empty()) {
      const std::size_t nl = data.find('\n');
      const std::string_view part = data.substr(0, nl);
      if (!c.discarding) c.in.append(part);
      if (nl == std::string_view::npos) {
        if (c.in.size() > kMaxLineBytes) {
          c.out += error_reply(nullptr, error_code::kLineTooLong,
                               fmt::format("a request line is at most {} bytes", kMaxLineBytes))
                       .dump() +
                   "\n";
          c.in.clear();
          c.discarding = true;
        }
        break;
      }
      if (!c.discarding) answer(c, c.in);
      c.in.clear();
      c.discarding = false;
      data.remove_prefix(nl + 1);
    }
    if (c.out.size() > kMaxPendingBytes) return false;
  }
  return true;
}

void ControlServer::answer(Client& c, std::string_view line) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  if (line.find_first_not_of(" \t") == std::string_view::npos) return;  // blank lines are ignored
  json request = json::parse(line, nullptr, false);
  json reply;
  const auto cmd = request.is_object() ? request.find("cmd") : request.end();
  const bool stream_cmd = request.is_object() && cmd != request.end() && cmd->is_string() &&
                          (*cmd == "subscribe" || *cmd == "unsubscribe");
  if (!stream_cmd) {
    c.out += handler_.handle_line(line);
    c.out += '\n';
    return;
  }
  const json id = request.value("id", json(nullptr));
  if (*cmd == "unsubscribe") {
    c.subscribed = false;
    reply = json{{"id", id}, {"result", {{"subscribed", false}}}};
  } else {
    EventQueue& q = handler_.events();
    std::uint64_t since = q.next_seq();
    if (const auto s = request.find("since"); s != request.end()) {
      if (!s->is_number_integer() || s->get<std::int64_t>() < 0) {
        c.out += error_reply(id, error_code::kBadRequest, "\"since\": an event sequence number is needed").dump() + "\n";
        return;
      }
      since = s->get<std::uint64_t>();
    }
    c.subscribed = true;
    c.cursor = since;
    reply = json{{"id", id}, {"result", {{"subscribed", true}, {"next", since}}}};
  }
  c.out += reply.dump(-1, ' ', false, json::error_handler_t::replace);
  c.out += '\n';
}

void ControlServer::stream_events(Client& c) {
  const json batch = handler_.events().since(c.cursor, kEventsPerTick);
  if (const std::uint64_t lost = batch["lost"].get<std::uint64_t>(); lost > 0) {
    c.out += json{{"event", {{"type", "events_lost"}, {"count", lost}}}}.dump() + "\n";
  }
  for (const json& e : batch["events"]) {
    c.out += json{{"event", e}}.dump(-1, ' ', false, json::error_handler_t::replace);
    c.out += '\n';
  }
  c.cursor = batch["next"].get<std::uint64_t>();
}

bool ControlServer::flush(Client& c) {
  while (!c.out.empty()) {
    const ssize_t n = ::send(c.fd, c.out.data(), c.out.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) break;
      return false;
    }
    c.out.erase(0, static_cast<std::size_t>(n));
  }
  return c.out.size() <= kMaxPendingBytes;
}

}  // namespace ecat::control
