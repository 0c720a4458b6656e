#include "transport/raw_socket_transport.hpp"

#include "transport/socket_timestamp.hpp"

#include <arpa/inet.h>
#include <grp.h>
#include <linux/if_packet.h>
#include <net/ethernet.h>
#include <net/if.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace ecat::transport {

namespace {

TransportError open_error(int err) noexcept {
  return (err == EPERM || err == EACCES) ? TransportError::PermissionDenied : TransportError::OpenFailed;
}

}  // namespace

Expected<RawSocketTransport, TransportError> RawSocketTransport::open(std::string_view interface_name,
                                                                     RawSocketOptions options) {
  std::string name(interface_name);
  if (name.empty() || name.size() >= IFNAMSIZ) return fail(TransportError::OpenFailed);
  const unsigned ifindex = ::if_nametoindex(name.c_str());
  if (ifindex == 0) return fail(TransportError::OpenFailed);

  // Protocol 0x88A4: the kernel delivers only EtherCAT frames to this socket.
  UniqueFd fd(::socket(AF_PACKET, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, htons(kEtherTypeEthercat)));
  if (!fd.valid()) return fail(open_error(errno));

  bool ignore_outgoing = false;
#ifdef PACKET_IGNORE_OUTGOING
  int one = 1;
  ignore_outgoing = ::setsockopt(fd.get(), SOL_PACKET, PACKET_IGNORE_OUTGOING, &one, sizeof one) == 0;
#endif

  sockaddr_ll addr{};
  addr.sll_family = AF_PACKET;
  addr.sll_protocol = htons(kEtherTypeEthercat);
  addr.sll_ifindex = static_cast<int>(ifindex);
  if (::bind(fd.get(), reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
    return fail(open_error(errno));
  }
  if (options.promiscuous) {
    packet_mreq mreq{};
    mreq.mr_ifindex = static_cast<int>(ifindex);
    mreq.mr_type = PACKET_MR_PROMISC;
    // Promiscuous membership is released by the kernel when the socket closes.
    if (::setsockopt(fd.get(), SOL_PACKET, PACKET_ADD_MEMBERSHIP, &mreq, sizeof mreq) != 0) {
      return fail(open_error(errno));
    }
  }
  // Kernel receive timestamps: best effort (without them frames carry no arrival time).
  (void)enable_receive_timestamps(fd.get());
  // Drop whatever arrived between socket() and bind() on other interfaces.
  std::uint8_t scratch[kMaxFrameSize];
  while (::recv(fd.get(), scratch, sizeof scratch, MSG_DONTWAIT) >= 0) {
  }
  return RawSocketTransport(std::move(fd), std::move(name), static_cast<int>(ifindex), ignore_outgoing);
}

Expected<void, TransportError> RawSocketTransport::send(ConstBytes frame) {
  if (!fd_.valid()) return fail(TransportError::NotOpen);
  if (frame.size() > kMaxFrameSize) return fail(TransportError::FrameTooLarge);
  if (ether_type_of(frame) != kEtherTypeEthercat) return fail(TransportError::InvalidFrame);
  for (int attempt = 0; attempt < 3; ++attempt) {
    const ssize_t n = ::send(fd_.get(), frame.data(), frame.size(), 0);
    if (n == static_cast<ssize_t>(frame.size())) return {};
    if (n < 0 && errno == EINTR) continue;
    last_errno_ = n < 0 ? errno : EMSGSIZE;
    return fail(TransportError::SendFailed);
  }
  last_errno_ = EINTR;
  return fail(TransportError::SendFailed);
}

Expected<std::size_t, TransportError> RawSocketTransport::receive(Bytes buffer, Nanoseconds timeout) {
  auto r = receive_stamped(buffer, timeout);
  if (!r) return fail(r.error());
  return r->length;
}

Expected<Received, TransportError> RawSocketTransport::receive_stamped(Bytes buffer, Nanoseconds timeout) {
  if (!fd_.valid()) return fail(TransportError::NotOpen);
  if (auto w = wait_readable(fd_.get(), timeout); !w) return fail(w.error());
  sockaddr_ll from{};
  iovec iov{buffer.data(), buffer.size()};
  alignas(cmsghdr) std::uint8_t control[kTimestampControlSize];
  msghdr msg{};
  msg.msg_name = &from;
  msg.msg_namelen = sizeof from;
  msg.msg_iov = &iov;
  msg.msg_iovlen = 1;
  msg.msg_control = control;
  msg.msg_controllen = sizeof control;
  // MSG_TRUNC: the return value is the real length, so a short buffer is detected.
  const ssize_t n = ::recvmsg(fd_.get(), &msg, MSG_TRUNC);
  if (n < 0) {
    last_errno_ = errno;
    if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return fail(TransportError::Timeout);
    return fail(TransportError::ReceiveFailed);
  }
  if (!ignore_outgoing_ && from.sll_pkttype == PACKET_OUTGOING) return fail(TransportError::Timeout);
  if (static_cast<std::size_t>(n) > buffer.size()) return fail(TransportError::BufferTooSmall);
  return Received{static_cast<std::size_t>(n), arrival_time(msg)};
}

Expected<void, TransportError> drop_privileges(uid_t uid, gid_t gid) noexcept {
  if (::geteuid() == 0 && ::setgroups(0, nullptr) != 0) return fail(TransportError::PermissionDenied);
  if (::setresgid(gid, gid, gid) != 0) return fail(TransportError::PermissionDenied);
  if (::setresuid(uid, uid, uid) != 0) return fail(TransportError::PermissionDenied);
  if (uid != 0 && ::setuid(0) == 0) return fail(TransportError::PermissionDenied);
  return {};
}

Expected<void, TransportError> drop_privileges() noexcept {
  if (::geteuid() != 0) return {};
  constexpr uid_t kNobody = 65534;
  uid_t uid = kNobody;
  gid_t gid = kNobody;
  // Edge helper for main(): reading the environment is fine here.
  if (const char* s = std::getenv("SUDO_UID")) uid = static_cast<uid_t>(std::strtoul(s, nullptr, 10));
  if (const char* s = std::getenv("SUDO_GID")) gid = static_cast<gid_t>(std::strtoul(s, nullptr, 10));
  if (uid == 0) uid = kNobody;
  if (gid == 0) gid = kNobody;
  return drop_privileges(uid, gid);
}

}  // namespace ecat::transport
