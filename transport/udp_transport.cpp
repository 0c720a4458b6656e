#include "transport/udp_transport.hpp"

#include <netdb.h>
#include <netinet/in.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
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
  int one = 1;
  (void)::setsockopt(fd.get(), SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (::bind(fd.get(), ai.ai_addr, ai.ai_addrlen) != 0) {
    return fail(errno == EACCES ? TransportError::PermissionDenied : TransportError::OpenFailed);
  }
  return UdpTransport(std::move(fd), false);
}

std::uint16_t UdpTransport::local_port() const noexcept {
  sockaddr_storage a{};
  socklen_t len = sizeof a;
  if (::getsockname(fd_.get(), reinterpret_cast<sockaddr*>(&a), &len) != 0) return 0;
  if (a.ss_family == AF_INET) return ntohs(reinterpret_cast<const sockaddr_in*>(&a)->sin_port);
  if (a.ss_family == AF_INET6) return ntohs(reinterpret_cast<const sockaddr_in6*>(&a)->sin6_port);
  return 0;
}

Expected<void, TransportError> UdpTransport::send(ConstBytes frame) {
  if (!fd_.valid()) return fail(TransportError::NotOpen);
  if (frame.size() > kMaxFrameSize) return fail(TransportError::FrameTooLarge);
  if (ether_type_of(frame) != kEtherTypeEthercat) return fail(TransportError::InvalidFrame);
  const ConstBytes payload = frame.subspan(kEthernetHeaderSize);
  ssize_t n = -1;
  if (connected_) {
    n = ::send(fd_.get(), payload.data(), payload.size(), 0);
    // An ICMP "port unreachable" for an earlier datagram is reported once on
    // the next call: nobody listened then; send this one anyway.
    if (n < 0 && errno == ECONNREFUSED) n = ::send(fd_.get(), payload.data(), payload.size(), 0);
  } else {
    if (peer_len_ == 0) return fail(TransportError::NotOpen);  // nobody to answer yet
    n = ::sendto(fd_.get(), payload.data(), payload.size(), 0,
                 reinterpret_cast<const sockaddr*>(&peer_), peer_len_);
  }
  if (n != static_cast<ssize_t>(payload.size())) {
    last_errno_ = n < 0 ? errno : EMSGSIZE;
    return fail(TransportError::SendFailed);
  }
  return {};
}

Expected<std::size_t, TransportError> UdpTransport::receive(Bytes buffer, Nanoseconds timeout) {
  auto r = receive_stamped(buffer, timeout);
  if (!r) return fail(r.error());
  return r->length;
}

Expected<Received, TransportError> UdpTransport::receive_stamped(Bytes buffer, Nanoseconds timeout) {
  if (!fd_.valid()) return fail(TransportError::NotOpen);
  if (buffer.size() < kEthernetHeaderSize) return fail(TransportError::BufferTooSmall);
  if (auto w = wait_readable(fd_.get(), timeout); !w) return fail(w.error());
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
  const ssize_t n = ::recvmsg(fd_.get(), &msg, MSG_TRUNC);
  const socklen_t from_len = msg.msg_namelen;
  if (n < 0) {
    last_errno_ = errno;
    // A connected UDP socket reports an ICMP "port unreachable" here: no slave yet.
    if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR || errno == ECONNREFUSED) {
      return fail(TransportError::Timeout);
    }
    return fail(TransportError::ReceiveFailed);
  }
  if (static_cast<std::size_t>(n) > payload.size() || static_cast<std::size_t>(n) > kMaxUdpPayload) {
    return fail(TransportError::BufferTooSmall);
  }
  if (!connected_) {
    peer_ = from;
    peer_len_ = from_len;
  }
  std::memset(buffer.data(), 0xFF, kMacSize);                // destination: broadcast
  std::memset(buffer.data() + kMacSize, 0x00, kMacSize);     // source: unknown
  buffer[kEtherTypeOffset] = static_cast<std::uint8_t>(kEtherTypeEthercat >> 8);
  buffer[kEtherTypeOffset + 1] = static_cast<std::uint8_t>(kEtherTypeEthercat & 0xFF);
  return Received{kEthernetHeaderSize + static_cast<std::size_t>(n), arrival_time(msg)};
}

}  // namespace ecat::transport
