// Kernel receive timestamps (socket(7) SO_TIMESTAMPNS): the kernel stamps
// each frame when the network stack takes it, before the process that reads
// it is scheduled. A slave woken late can so still process each frame at the
// moment it arrived, as an ESC stamps a frame in silicon (docs/e2e.md "Live
// timing"). The stamp is CLOCK_REALTIME; it is handed on in the steady
// clock's time base (CLOCK_MONOTONIC, SteadyClock), which a wall-clock step
// does not move.
#pragma once

#include <sys/socket.h>
#include <time.h>

#include <cstddef>
#include <optional>

#include "common/clock.hpp"

namespace ecat::transport {

// Asks the kernel to stamp received frames; false when it will not (the
// frames then carry no arrival time).
bool enable_receive_timestamps(int fd) noexcept;

// Control-message room for one SCM_TIMESTAMPNS.
inline constexpr std::size_t kTimestampControlSize = CMSG_SPACE(sizeof(timespec));

// The arrival time in a received message's control data, on the steady
// clock; nullopt when the message carries none.
std::optional<Nanoseconds> arrival_time(const msghdr& message) noexcept;

// A CLOCK_REALTIME stamp moved to CLOCK_MONOTONIC, given both clocks read
// now: the frame arrived (realtime_now - stamp) before steady_now.
constexpr Nanoseconds to_steady(Nanoseconds stamp, Nanoseconds realtime_now, Nanoseconds steady_now) noexcept {
  return steady_now - (realtime_now - stamp);
}

}  // namespace ecat::transport
