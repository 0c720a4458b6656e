// EtherCAT frames in UDP datagrams, port 0x88A4 (ETG.1000.4 §5.3): the UDP
// payload is the EtherCAT header plus datagrams, i.e. the Ethernet frame
// without its 14-byte Ethernet header. send() strips the header of the frame it
// is given; receive() puts a synthetic one in front (destination broadcast,
// source 00:00:00:00:00:00, EtherType 0x88A4), so callers see whole frames as
// with every other transport.
#pragma once

#include <sys/socket.h>

#include <cstdint>
#include <string>
#include <string_view>

#include "transport/transport.hpp"
#include "transport/unique_fd.hpp"

namespace ecat::transport {

struct UdpEndpoint {
  std::string host;  // numeric IPv4/IPv6 address or host name
  std::uint16_t port = kUdpPortEthercat;
};

// "ADDR:PORT", "ADDR" (port 0x88A4) or "[v6addr]:PORT".
Expected<UdpEndpoint, TransportError> parse_udp_endpoint(std::string_view text);

class UdpTransport final : public Transport {
 public:
  // Master side: an ephemeral local port, connected to `remote`.
  static Expected<UdpTransport, TransportError> connect(const UdpEndpoint& remote);
  // Device side: bound to `local`; send() answers whoever sent the last frame.
  static Expected<UdpTransport, TransportError> bind(const UdpEndpoint& local);

  Expected<void, TransportError> send(ConstBytes frame) override;
  Expected<std::size_t, TransportError> receive(Bytes buffer, Nanoseconds timeout) override;
  // With the kernel's receive timestamp (SO_TIMESTAMPNS).
  Expected<Received, TransportError> receive_stamped(Bytes buffer, Nanoseconds timeout) override;

  std::uint16_t local_port() const noexcept;
  int last_os_error() const noexcept { return last_errno_; }

 private:
  UdpTransport(UniqueFd fd, bool connected) noexcept : fd_(std::move(fd)), connected_(connected) {}

  UniqueFd fd_;
  bool connected_ = false;
  sockaddr_storage peer_{};
  socklen_t peer_len_ = 0;
  int last_errno_ = 0;
};

}  // namespace ecat::transport
