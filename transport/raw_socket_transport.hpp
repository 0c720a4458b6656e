// Linux AF_PACKET transport: whole Ethernet frames on one named interface,
// EtherType 0x88A4 only (the socket protocol filters in the kernel), never our
// own sends (PACKET_IGNORE_OUTGOING, Linux >= 4.20), non-blocking with ppoll()
// timeouts. Needs CAP_NET_RAW; call drop_privileges() once it is open.
#pragma once

#include <sys/types.h>

#include <string>
#include <string_view>

#include "transport/transport.hpp"
#include "transport/unique_fd.hpp"

namespace ecat::transport {

struct RawSocketOptions {
  // Also receive frames not addressed to this NIC (EtherCAT replies keep the
  // master's destination address, which is usually broadcast anyway).
  bool promiscuous = true;
};

class RawSocketTransport final : public Transport {
 public:
  static Expected<RawSocketTransport, TransportError> open(std::string_view interface_name,
                                                          RawSocketOptions options = {});

  Expected<void, TransportError> send(ConstBytes frame) override;
  Expected<std::size_t, TransportError> receive(Bytes buffer, Nanoseconds timeout) override;
  // With the kernel's receive timestamp (SO_TIMESTAMPNS).
  Expected<Received, TransportError> receive_stamped(Bytes buffer, Nanoseconds timeout) override;

  const std::string& interface_name() const noexcept { return name_; }
  // The socket, to wait on several transports with one poll() (a slave
  // segment with a redundant port serves two interfaces).
  int fd() const noexcept { return fd_.get(); }
  int interface_index() const noexcept { return ifindex_; }
  // False on kernels without PACKET_IGNORE_OUTGOING: then our own frames are
  // filtered in receive() by comparing with the last frame sent.
  bool ignores_outgoing() const noexcept { return ignore_outgoing_; }
  // errno of the last failed system call (0 if none), for messages at the edge.
  int last_os_error() const noexcept { return last_errno_; }

 private:
  RawSocketTransport(UniqueFd fd, std::string name, int ifindex, bool ignore_outgoing) noexcept
      : fd_(std::move(fd)), name_(std::move(name)), ifindex_(ifindex), ignore_outgoing_(ignore_outgoing) {}

  UniqueFd fd_;
  std::string name_;
  int ifindex_ = 0;
  bool ignore_outgoing_ = false;
  int last_errno_ = 0;
};

// Gives up root after the raw socket is open: supplementary groups cleared,
// then gid and uid set. Fails if root could be regained afterwards.
Expected<void, TransportError> drop_privileges(uid_t uid, gid_t gid) noexcept;
// The same to the invoking user under sudo (SUDO_UID/SUDO_GID), else to
// "nobody" (65534). No-op when not running as root.
Expected<void, TransportError> drop_privileges() noexcept;

}  // namespace ecat::transport
