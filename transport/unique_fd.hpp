// RAII owner of a POSIX file descriptor, and a poll() wait on it, shared by the
// socket transports. Nothing here sleeps except the explicit wait.
#pragma once

#include <utility>

#include "common/clock.hpp"
#include "common/expected.hpp"
#include "transport/transport.hpp"

namespace ecat::transport {

class UniqueFd {
 public:
  UniqueFd() noexcept = default;
  explicit UniqueFd(int fd) noexcept : fd_(fd) {}
  UniqueFd(UniqueFd&& o) noexcept : fd_(std::exchange(o.fd_, -1)) {}
  UniqueFd& operator=(UniqueFd&& o) noexcept {
    if (this != &o) {
      reset();
      fd_ = std::exchange(o.fd_, -1);
    }
    return *this;
  }
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;
  ~UniqueFd() { reset(); }

  int get() const noexcept { return fd_; }
  bool valid() const noexcept { return fd_ >= 0; }
  void reset() noexcept;

 private:
  int fd_ = -1;
};

// Waits until `fd` is readable; Timeout when the time ran out or a signal
// interrupted the wait (EINTR), ReceiveFailed on socket errors.
Expected<void, TransportError> wait_readable(int fd, Nanoseconds timeout) noexcept;

}  // namespace ecat::transport
