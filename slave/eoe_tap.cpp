#include "slave/eoe_tap.hpp"

#include <fcntl.h>
#include <linux/if.h>
#include <linux/if_tun.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace ecat::slave {

Expected<std::unique_ptr<EoeTap>, std::string> EoeTap::open(const std::string& name, coe::EoeServer& server) {
  if (name.empty() || name.size() >= IFNAMSIZ) {
    return fail(std::string("--eoe-tap: interface name must be 1..") + std::to_string(IFNAMSIZ - 1) + " characters");
  }
  const int fd = ::open("/dev/net/tun", O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return fail(std::string("--eoe-tap: /dev/net/tun: ") + std::strerror(errno));
  ifreq ifr{};
  ifr.ifr_flags = IFF_TAP | IFF_NO_PI;
  std::memcpy(ifr.ifr_name, name.data(), name.size());
  if (::ioctl(fd, TUNSETIFF, &ifr) < 0) {
    const int e = errno;
    ::close(fd);
    return fail("--eoe-tap " + name + ": " + std::strerror(e) + (e == EPERM ? " (needs CAP_NET_ADMIN)" : ""));
  }
  auto tap = std::unique_ptr<EoeTap>(new EoeTap(fd, ifr.ifr_name, server));
  server.set_port(tap.get());
  return tap;
}

EoeTap::~EoeTap() {
  server_.set_port(nullptr);
  if (fd_ >= 0) ::close(fd_);
}

void EoeTap::close_tap() noexcept {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

void EoeTap::receive(ConstBytes frame) noexcept {
  if (fd_ < 0) return (void)++stats_.write_errors;
  const ssize_t n = ::write(fd_, frame.data(), frame.size());
  if (n == static_cast<ssize_t>(frame.size())) return (void)++stats_.to_host;
  ++stats_.write_errors;
  // EAGAIN: the interface is down or its queue is full - drop this frame only.
  if (n < 0 && errno != EAGAIN && errno != EINTR) close_tap();
}

std::size_t EoeTap::service(std::size_t max_frames) noexcept {
  std::size_t queued = 0;
  // Frames beyond what the server can hold stay in the kernel's queue.
  while (fd_ >= 0 && queued < max_frames && server_.tx_waiting() < coe::eoe::kTxFrames) {
    const ssize_t n = ::read(fd_, buffer_.data(), buffer_.size());
    if (n < 0) {
      if (errno == EAGAIN || errno == EINTR) break;
      ++stats_.read_errors;
      close_tap();
      break;
    }
    if (n == 0) break;
    if (!server_.transmit({buffer_.data(), static_cast<std::size_t>(n)})) {
      ++stats_.refused;
      continue;
    }
    ++stats_.from_host;
    ++queued;
  }
  return queued;
}

}  // namespace ecat::slave
