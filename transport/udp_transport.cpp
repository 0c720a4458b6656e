#include "transport/udp_transport.hpp"

#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <ctime>
#include <memory>
#include <string>

#include "transport/socket_timestamp.hpp"

namespace ecat::transport {

namespace {

// Largest UDP payload we accept: an Ethernet frame without its header.
constexpr std::size_t kMaxUdpPayload = kMaxFrameSize - kEthernetHeaderSize;

struct AddrInfoDeleter {
  void operator()(addrinfo* a) const noexcept { ::freeaddrinfo(a); }
};

// Resolves `ep` and opens a socket of the first usable family; the chosen
// address is copied into `addr` (`chosen.ai_addr` points at it).
Expected<void, TransportError> open_socket(const UdpEndpoint& ep, bool passive,
                                                   UniqueFd& out, addrinfo& chosen,
                                                   sockaddr_storage& addr) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_DGRAM;
  hints.ai_flags = passive ? AI_PASSIVE : 0;
  addrinfo* list = nullptr;
  const std::string port = std::to_string(ep.port);
  if (::getaddrinfo(ep.host.empty() ? nullptr : ep.host.c_str(), port.c_str(), &hints, &list) != 0) {
    return fail(TransportError::OpenFailed);
  }
  std::unique_ptr<addrinfo, AddrInfoDeleter> guard(list);
  for (addrinfo* a = list; a != nullptr; a = a->ai_next) {
    UniqueFd fd(::socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol));
    if (!fd.valid()) continue;
    // Kernel receive timestamps: best effort (without them frames carry no arrival time).
    (void)enable_receive_timestamps(fd.get());
    out = std::move(fd);
    chosen = *a;
    std::memcpy(&addr, a->ai_addr, a->ai_addrlen);
    chosen.ai_addr = reinterpret_cast<sockaddr*>(&addr);
    chosen.ai_next = nullptr;
    return {};
  }
  return fail(TransportError::OpenFailed);
}

Expected<void, TransportError> bind_socket(const UniqueFd& fd, const sockaddr* addr, socklen_t len) {
  // No SO_REUSEADDR: on Linux it would let another socket bind the same
  // UDP address and port and take the master's datagrams.
  if (::bind(fd.get(), addr, len) != 0) {
    return fail(errno == EACCES ? TransportError::PermissionDenied : TransportError::OpenFailed);
  }
  return {};
}

}  // namespace

Expected<UdpEndpoint, TransportError> parse_udp_endpoint(std::string_view text) {
  UdpEndpoint ep;
  std::string_view host = text;
  std::string_view port;
  if (!text.empty() && text.front() == '[') {
    const auto close = text.find(']');
    if (close == std::string_view::npos) return fail(TransportError::OpenFailed);
    host = text.substr(1, close - 1);
    std::string_view rest = text.substr(close + 1);
    if (!rest.empty()) {
      if (rest.front() != ':' || rest.size() == 1) return fail(TransportError::OpenFailed);
      port = rest.substr(1);
    }
  } else if (const auto colon = text.rfind(':'); colon != std::string_view::npos) {
    if (text.find(':') != colon) return fail(TransportError::OpenFailed);  // bare IPv6 needs []
    host = text.substr(0, colon);
    port = text.substr(colon + 1);
    if (port.empty()) return fail(TransportError::OpenFailed);
  }
  if (host.empty()) return fail(TransportError::OpenFailed);
  ep.host = std::string(host);
  if (!port.empty()) {
    unsigned value = 0;
    const auto [ptr, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
    if (ec != std::errc{} || ptr != port.data() + port.size() || value == 0 || value > 0xFFFF) {
      return fail(TransportError::OpenFailed);
    }
    ep.port = static_cast<std::uint16_t>(value);
  }
  return ep;
}

bool udp_payload_length_consistent(ConstBytes payload) noexcept {
  if (payload.size() < kFrameHeaderSize) return false;
  const std::size_t declared = load_le<std::uint16_t>(payload.data()) & kFrameLengthMask;
  return kFrameHeaderSize + declared == payload.size();
}

Expected<UdpTransport, TransportError> UdpTransport::connect(const UdpEndpoint& remote) {
  UniqueFd fd;
  addrinfo ai{};
  sockaddr_storage addr{};
  if (auto r = open_socket(remote, false, fd, ai, addr); !r) return fail(r.error());
  if (::connect(fd.get(), ai.ai_addr, ai.ai_addrlen) != 0) return fail(TransportError::OpenFailed);
  return UdpTransport(std::move(fd), true);
}

Expected<UdpTransport, TransportError> UdpTransport::bind(const UdpEndpoint& local) {
  UniqueFd fd;
  addrinfo ai{};
  sockaddr_storage addr{};
  if (auto r = open_socket(local, true, fd, ai, addr); !r) return fail(r.error());
  if (auto b = bind_socket(fd, ai.ai_addr, ai.ai_addrlen); !b) return fail(b.error());
  return UdpTransport(std::move(fd), false);
}

Expected<UdpTransport, TransportError> UdpTransport::bind_loopback(std::uint16_t port) {
  sockaddr_in v4{};
  v4.sin_family = AF_INET;
  v4.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  v4.sin_port = htons(port);
  UniqueFd fd4(::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
  if (!fd4.valid()) return fail(TransportError::OpenFailed);
  (void)enable_receive_timestamps(fd4.get());  // best effort, as open_socket
  if (auto b = bind_socket(fd4, reinterpret_cast<const sockaddr*>(&v4), sizeof v4); !b) return fail(b.error());
  UdpTransport t(std::move(fd4), false);
  sockaddr_in6 v6{};
  v6.sin6_family = AF_INET6;
  v6.sin6_addr = in6addr_loopback;
  v6.sin6_port = htons(t.local_port());
  UniqueFd fd6(::socket(AF_INET6, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
  if (!fd6.valid()) {
    if (errno == EAFNOSUPPORT) return t;  // no IPv6 in this kernel: 127.0.0.1 alone
    return fail(TransportError::OpenFailed);
  }
  int one = 1;
  (void)::setsockopt(fd6.get(), IPPROTO_IPV6, IPV6_V6ONLY, &one, sizeof one);
  (void)enable_receive_timestamps(fd6.get());
  if (auto b = bind_socket(fd6, reinterpret_cast<const sockaddr*>(&v6), sizeof v6); !b) {
    // ::1 absent (IPv6 disabled on lo): 127.0.0.1 alone. Anything else
    // (port taken on ::1) is an error: the slave would be half reachable.
    if (errno == EADDRNOTAVAIL) return t;
    return fail(b.error());
  }
  t.add(std::move(fd6));
  return t;
}

std::uint16_t UdpTransport::local_port() const noexcept {
  sockaddr_storage a{};
  socklen_t len = sizeof a;
  if (::getsockname(fds_[0].get(), reinterpret_cast<sockaddr*>(&a), &len) != 0) return 0;
  if (a.ss_family == AF_INET) return ntohs(reinterpret_cast<const sockaddr_in*>(&a)->sin_port);
  if (a.ss_family == AF_INET6) return ntohs(reinterpret_cast<const sockaddr_in6*>(&a)->sin6_port);
  return 0;
}

bool UdpTransport::loopback_only() const noexcept {
  // RFC 1122 §3.2.1.3 (127.0.0.0/8, as ::ffff:127.0.0.0/104) and RFC 4291 §2.5.3 (::1).
  static constexpr IpPrefix kLoopbackV4{{0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xFF, 0xFF, 127, 0, 0, 0}, 104};
  static constexpr IpPrefix kLoopbackV6{{0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1}, 128};
  for (std::size_t i = 0; i < count_; ++i) {
    sockaddr_storage a{};
    socklen_t len = sizeof a;
    std::array<std::uint8_t, IpPrefix::kAddressBytes> ip{};
    if (::getsockname(fds_[i].get(), reinterpret_cast<sockaddr*>(&a), &len) != 0 || !ip_of(a, ip)) return false;
    if (!kLoopbackV4.contains(ip) && !kLoopbackV6.contains(ip)) return false;
  }
  return count_ > 0;
}

Expected<void, TransportError> UdpTransport::send(ConstBytes frame) {
  if (count_ == 0 || !fds_[0].valid()) return fail(TransportError::NotOpen);
  if (frame.size() > kMaxFrameSize) return fail(TransportError::FrameTooLarge);
  if (ether_type_of(frame) != kEtherTypeEthercat) return fail(TransportError::InvalidFrame);
  ConstBytes payload = frame.subspan(kEthernetHeaderSize);
  // Ethernet padding after the EtherCAT frame (frame_builder pads to 60
  // bytes) is not part of the UDP payload (ETG.1000.4 §5.3).
  if (payload.size() >= kFrameHeaderSize) {
    const std::size_t whole = kFrameHeaderSize + (load_le<std::uint16_t>(payload.data()) & kFrameLengthMask);
    if (whole < payload.size()) payload = payload.first(whole);
  }
  ssize_t n = -1;
  if (connected_) {
    n = ::send(fds_[0].get(), payload.data(), payload.size(), 0);
    // An ICMP "port unreachable" for an earlier datagram is reported once on
    // the next call: nobody listened then; send this one anyway.
    if (n < 0 && errno == ECONNREFUSED) n = ::send(fds_[0].get(), payload.data(), payload.size(), 0);
  } else {
    if (peer_len_ == 0) return fail(TransportError::NotOpen);  // nobody to answer yet
    // No amplification: one reply per request, never longer than it.
    if (payload.size() > request_size_) {
      ++stats_.replies_refused;
      return fail(request_size_ == 0 ? TransportError::NotOpen : TransportError::FrameTooLarge);
    }
    request_size_ = 0;
    n = ::sendto(fds_[peer_fd_].get(), payload.data(), payload.size(), 0,
                 reinterpret_cast<const sockaddr*>(&peer_), peer_len_);
  }
  if (n != static_cast<ssize_t>(payload.size())) {
    last_errno_ = n < 0 ? errno : EMSGSIZE;
    return fail(TransportError::SendFailed);
  }
  return {};
}

Expected<std::size_t, TransportError> UdpTransport::wait_any(Nanoseconds timeout) noexcept {
  if (count_ == 1) {
    if (auto w = wait_readable(fds_[0].get(), timeout); !w) return fail(w.error());
    return std::size_t{0};
  }
  if (timeout < Nanoseconds{0}) timeout = Nanoseconds{0};
  constexpr long kNanosPerSecond = 1'000'000'000L;
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(timeout.count() / kNanosPerSecond);
  ts.tv_nsec = static_cast<long>(timeout.count() % kNanosPerSecond);
  std::array<pollfd, kMaxSockets> p{};
  for (std::size_t i = 0; i < count_; ++i) {
    p[i].fd = fds_[i].get();
    p[i].events = POLLIN;
  }
  const int r = ::ppoll(p.data(), count_, &ts, nullptr);
  if (r == 0 || (r < 0 && errno == EINTR)) return fail(TransportError::Timeout);
  if (r < 0) return fail(TransportError::ReceiveFailed);
  // Start with a different socket each time, so a flood on one address
  // cannot starve the other.
  for (std::size_t k = 0; k < count_; ++k) {
    const std::size_t i = (next_first_ + k) % count_;
    if ((p[i].revents & POLLNVAL) != 0) return fail(TransportError::NotOpen);
    if (p[i].revents != 0) {
      next_first_ = (i + 1) % count_;
      return i;
    }
  }
  return fail(TransportError::Timeout);
}

Expected<std::size_t, TransportError> UdpTransport::receive(Bytes buffer, Nanoseconds timeout) {
  auto r = receive_stamped(buffer, timeout);
  if (!r) return fail(r.error());
  return r->length;
}

Expected<Received, TransportError> UdpTransport::receive_stamped(Bytes buffer, Nanoseconds timeout) {
  if (count_ == 0 || !fds_[0].valid()) return fail(TransportError::NotOpen);
  if (buffer.size() < kEthernetHeaderSize) return fail(TransportError::BufferTooSmall);
  auto which = wait_any(timeout);
  if (!which) return fail(which.error());
  sockaddr_storage from{};
  const Bytes payload = buffer.subspan(kEthernetHeaderSize);
  iovec iov{payload.data(), payload.size()};
  alignas(cmsghdr) std::uint8_t control[kTimestampControlSize];
  msghdr msg{};
  msg.msg_name = &from;
  msg.msg_namelen = sizeof from;
  msg.msg_iov = &iov;
  msg.msg_iovlen = 1;
  msg.msg_control = control;
  msg.msg_controllen = sizeof control;
  const ssize_t n = ::recvmsg(fds_[*which].get(), &msg, MSG_TRUNC);
  const socklen_t from_len = msg.msg_namelen;
  if (n < 0) {
    last_errno_ = errno;
    // A connected UDP socket reports an ICMP "port unreachable" here: no slave yet.
    if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR || errno == ECONNREFUSED) {
      return fail(TransportError::Timeout);
    }
    return fail(TransportError::ReceiveFailed);
  }
  const auto size = static_cast<std::size_t>(n);
  if (!connected_) {
    // Checked before anything else is looked at, so a refused peer learns
    // nothing (not even whether its datagram was well formed).
    if (!allow_.empty() && !allow_.allows(from)) {
      ++stats_.refused_source;
      return fail(TransportError::Dropped);
    }
  }
  if (size > payload.size() || size > kMaxUdpPayload) return fail(TransportError::BufferTooSmall);
  if (!connected_) {
    if (!udp_payload_length_consistent(payload.first(size))) {
      ++stats_.length_mismatch;
      return fail(TransportError::Dropped);
    }
    ++stats_.datagrams_accepted;
    peer_ = from;
    peer_len_ = from_len;
    peer_fd_ = *which;
    request_size_ = size;
  }
  std::memset(buffer.data(), 0xFF, kMacSize);                // destination: broadcast
  std::memset(buffer.data() + kMacSize, 0x00, kMacSize);     // source: unknown
  buffer[kEtherTypeOffset] = static_cast<std::uint8_t>(kEtherTypeEthercat >> 8);
  buffer[kEtherTypeOffset + 1] = static_cast<std::uint8_t>(kEtherTypeEthercat & 0xFF);
  return Received{kEthernetHeaderSize + size, arrival_time(msg)};
}

}  // namespace ecat::transport
