// A frame taken from a live medium long after it arrived is lost on the wire
// (issue 29 item 4, docs/e2e.md "Stale frames"). On a wire, a frame is
// processed by every ESC within microseconds of being sent; a frame that
// waited in the socket while the slave process was not scheduled would reach
// the ESCs after the master gave up on it and, for a retrying master, after
// its copy was sent again. Processing it then changes the slave behind the
// master's back (SOEM 2.x: a mailbox write that lands after the master's
// 2 ms timeout leaves every later reply answering the request before). Such
// a frame is dropped unprocessed, as if the wire had lost it, and the master
// retries it as it retries any lost frame.
#pragma once

#include <chrono>
#include <optional>

#include "common/clock.hpp"

namespace ecat::slave {

// The default age limit: SOEM's EC_TIMEOUTRET (2000 us), the time SOEM waits
// for one send of a frame before it sends it again (every datagram, mailbox
// writes included; shared/spec/masters.md §1.1: "2 ms each, <= 6 ms"). IgH
// gives up on a datagram sooner (500 us); ethercrab waits 30 ms without a
// retry, so a host too slow for 2 ms is better served with a larger limit
// there (--max-frame-age). A wire answers in microseconds, so no healthy
// frame comes near 2 ms.
inline constexpr Nanoseconds kDefaultMaxFrameAge = std::chrono::microseconds(2000);

// True when a frame that the medium stamped `arrival` and that is taken at
// `now` (same time base) waited longer than `max_age`: it is lost. Never for
// a frame without a stamp, and never with a max_age of 0 or less (off). A
// frame exactly max_age old is still processed.
constexpr bool frame_is_stale(std::optional<Nanoseconds> arrival, Nanoseconds now, Nanoseconds max_age) noexcept {
  return max_age > Nanoseconds{0} && arrival.has_value() && now - *arrival > max_age;
}

}  // namespace ecat::slave
