// EtherCAT frames in UDP datagrams, port 0x88A4 (ETG.1000.4 §5.3): the UDP
// payload is the EtherCAT header plus datagrams, i.e. the Ethernet frame
// without its 14-byte Ethernet header. send() strips the header of the frame it
// is given (and any Ethernet padding after the EtherCAT length); receive() puts
// a synthetic one in front (destination broadcast, source 00:00:00:00:00:00,
// EtherType 0x88A4), so callers see whole frames as with every other transport.
//
// The device side (bind) is what a remote master reaches, and EtherCAT-in-UDP
// has no authentication (docs/security.md), so it defends itself:
// * bind_loopback() serves 127.0.0.1 and ::1 only (ecat-slave's default);
// * an allow-list of source prefixes: other datagrams are dropped unanswered;
// * a datagram whose EtherCAT frame length (header bits 10:0) plus the 2-byte
//   header differs from the UDP payload length is dropped, as the raw path
//   drops a frame whose lengths disagree (the datagram chain inside is
//   checked against the frame length by the segment, common/frame_parser.hpp);
// * no amplification: one reply per request, never longer than the request.
// Every drop is counted in stats() and receive() returns Dropped.
#pragma once

#include <sys/socket.h>

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "transport/ip_allow_list.hpp"
#include "transport/transport.hpp"
#include "transport/unique_fd.hpp"

namespace ecat::transport {

struct UdpEndpoint {
  std::string host;  // numeric IPv4/IPv6 address or host name
  std::uint16_t port = kUdpPortEthercat;
};

// "ADDR:PORT", "ADDR" (port 0x88A4) or "[v6addr]:PORT".
Expected<UdpEndpoint, TransportError> parse_udp_endpoint(std::string_view text);

// Whether a UDP payload is one whole EtherCAT frame: at least the 2-byte
// frame header, and exactly as long as the header's length field says.
bool udp_payload_length_consistent(ConstBytes payload) noexcept;

// What the device side dropped or refused (ecat-slave --stats prints it).
struct UdpStats {
  std::uint64_t datagrams_accepted = 0;  // handed to the caller
  std::uint64_t refused_source = 0;      // source not in the allow-list: no answer
  std::uint64_t length_mismatch = 0;     // EtherCAT length != UDP length: no answer
  std::uint64_t replies_refused = 0;     // send() longer than the request, or a second reply
};

class UdpTransport final : public Transport {
 public:
  static constexpr std::size_t kMaxSockets = 2;

  // Master side: an ephemeral local port, connected to `remote`.
  static Expected<UdpTransport, TransportError> connect(const UdpEndpoint& remote);
  // Device side: bound to `local`; send() answers whoever sent the last frame.
  static Expected<UdpTransport, TransportError> bind(const UdpEndpoint& local);
  // Device side on the loopback addresses only: 127.0.0.1 and ::1, both on
  // `port` (0: the kernel picks one for 127.0.0.1 and ::1 gets the same).
  // Without IPv6 on the host, 127.0.0.1 alone.
  static Expected<UdpTransport, TransportError> bind_loopback(std::uint16_t port);

  // Device side: only datagrams from these prefixes are served (empty: all).
  void set_allow_list(IpAllowList list) { allow_ = std::move(list); }

  Expected<void, TransportError> send(ConstBytes frame) override;
  Expected<std::size_t, TransportError> receive(Bytes buffer, Nanoseconds timeout) override;
  // With the kernel's receive timestamp (SO_TIMESTAMPNS).
  Expected<Received, TransportError> receive_stamped(Bytes buffer, Nanoseconds timeout) override;

  std::uint16_t local_port() const noexcept;
  std::size_t socket_count() const noexcept { return count_; }
  // Socket i (< socket_count()), to wait on it with other descriptors.
  int socket_fd(std::size_t i) const noexcept { return fds_[i].get(); }
  // Whether every socket is bound to a loopback address (127.0.0.0/8, ::1):
  // then only this machine can reach the slave.
  bool loopback_only() const noexcept;
  const UdpStats& stats() const noexcept { return stats_; }
  int last_os_error() const noexcept { return last_errno_; }

 private:
  UdpTransport(UniqueFd fd, bool connected) noexcept : connected_(connected) { add(std::move(fd)); }
  void add(UniqueFd fd) noexcept { fds_[count_++] = std::move(fd); }
  // Index of a readable socket, Timeout when none became readable in time.
  Expected<std::size_t, TransportError> wait_any(Nanoseconds timeout) noexcept;

  std::array<UniqueFd, kMaxSockets> fds_;
  std::size_t count_ = 0;
  std::size_t next_first_ = 0;  // round robin among the sockets
  bool connected_ = false;
  IpAllowList allow_;
  sockaddr_storage peer_{};
  socklen_t peer_len_ = 0;
  std::size_t peer_fd_ = 0;
  std::size_t request_size_ = 0;  // UDP payload bytes of the request not answered yet
  UdpStats stats_;
  int last_errno_ = 0;
};

}  // namespace ecat::transport
