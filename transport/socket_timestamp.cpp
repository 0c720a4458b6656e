#include "transport/socket_timestamp.hpp"

#include <algorithm>
#include <cstring>

namespace ecat::transport {
namespace {

Nanoseconds read_clock(clockid_t id) noexcept {
  timespec ts{};
  (void)::clock_gettime(id, &ts);
  return Nanoseconds{std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec};
}

}  // namespace

bool enable_receive_timestamps(int fd) noexcept {
  int one = 1;
  return ::setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof one) == 0;
}

std::optional<Nanoseconds> arrival_time(const msghdr& message) noexcept {
  if ((message.msg_flags & MSG_CTRUNC) != 0) return std::nullopt;
  for (const cmsghdr* c = CMSG_FIRSTHDR(&message); c != nullptr;
       c = CMSG_NXTHDR(const_cast<msghdr*>(&message), const_cast<cmsghdr*>(c))) {
    if (c->cmsg_level != SOL_SOCKET || c->cmsg_type != SCM_TIMESTAMPNS) continue;
    timespec ts{};
    std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
    if (ts.tv_sec == 0 && ts.tv_nsec == 0) return std::nullopt;  // not stamped
    const Nanoseconds stamp{std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec};
    // Both clocks read back to back, just after the frame was taken.
    const Nanoseconds realtime_now = read_clock(CLOCK_REALTIME);
    const Nanoseconds steady_now = read_clock(CLOCK_MONOTONIC);
    // A wall-clock step between stamp and now would put the frame in the
    // future: it arrived no later than now.
    return std::min(to_steady(stamp, realtime_now, steady_now), steady_now);
  }
  return std::nullopt;
}

}  // namespace ecat::transport
