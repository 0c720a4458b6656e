#include "transport/unique_fd.hpp"

#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <ctime>

namespace ecat::transport {

void UniqueFd::reset() noexcept {
  if (fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
}

Expected<void, TransportError> wait_readable(int fd, Nanoseconds timeout) noexcept {
  if (fd < 0) return fail(TransportError::NotOpen);
  if (timeout < Nanoseconds{0}) timeout = Nanoseconds{0};
  constexpr long kNanosPerSecond = 1'000'000'000L;
  const auto ns = timeout.count();
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(ns / kNanosPerSecond);
  ts.tv_nsec = static_cast<long>(ns % kNanosPerSecond);
  pollfd p{};
  p.fd = fd;
  p.events = POLLIN;
  const int r = ::ppoll(&p, 1, &ts, nullptr);
  if (r > 0) {
    if ((p.revents & POLLNVAL) != 0) return fail(TransportError::NotOpen);
    return {};  // readable, or POLLERR: the receive call reports the socket error
  }
  // A signal ends the wait early like a timeout, so the caller's loop can
  // look at its shutdown flag.
  if (r == 0 || errno == EINTR) return fail(TransportError::Timeout);
  return fail(TransportError::ReceiveFailed);
}

}  // namespace ecat::transport
