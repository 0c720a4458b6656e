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

// The default age limit: half of SOEM's EC_TIMEOUTRET (2000 us), the time
// SOEM waits for one send of a frame before it sends it again or gives up
// (every datagram; shared/spec/masters.md §1.1: "2 ms each, <= 6 ms"). A
// frame taken at the limit still has the other half for its reply to be
// back in the master's socket before SOEM stops waiting: with the limit at
// the whole 2 ms, a frame taken just under it was answered after SOEM had
// given up (1 SDO-walk run in 20 lost a reply beside two CPU burners, 0 in
// 20 at 1 ms; docs/e2e.md "Stale frames"). IgH gives up on a datagram at
// 500 us and retries; ethercrab waits 30 ms without a retry, so a host too
// slow for 1 ms is better served with a larger limit there
// (--max-frame-age). A wire answers in microseconds: no healthy frame comes
// near 1 ms.
inline constexpr Nanoseconds kDefaultMaxFrameAge = std::chrono::microseconds(1000);

// True when a frame that the medium stamped `arrival` and that is taken at
// `now` (same time base) waited longer than `max_age`: it is lost. Never for
// a frame without a stamp, and never with a max_age of 0 or less (off). A
// frame exactly max_age old is still processed.
constexpr bool frame_is_stale(std::optional<Nanoseconds> arrival, Nanoseconds now, Nanoseconds max_age) noexcept {
  return max_age > Nanoseconds{0} && arrival.has_value() && now - *arrival > max_age;
}

}  // namespace ecat::slave
