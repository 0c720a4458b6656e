// Finds the events of a chain by comparing it with what it last saw, on a
// slow tick (ControlServer samples every 10 ms while a client is connected;
// a test on simulated time calls sample() itself): AL status 0x0130 and
// code 0x0134, AL control 0x0120, the link bits of DL status 0x0110, and the
// SDO writes and emergencies the CoE layer logs (coe::RecentLog). A few
// loads per slave per sample and nothing on the frame path. Changes that come
// and go between two samples are not seen (docs/control.md "Events").
#pragma once

#include <cstdint>
#include <vector>

#include "common/clock.hpp"
#include "control/event_queue.hpp"

namespace ecat::slave {
class Chain;
}

namespace ecat::control {

class EventWatcher {
 public:
  explicit EventWatcher(slave::Chain& chain);

  // Pushes an event for every change since the last sample (or since
  // construction / rebase()).
  void sample(Nanoseconds now, EventQueue& queue);
  // Takes the chain as it is now, without events.
  void rebase();

 private:
  struct Seen {
    std::uint16_t al_status = 0;
    std::uint16_t al_code = 0;
    std::uint16_t al_control = 0;
    std::uint16_t dl_status = 0;
    std::uint64_t sdo_writes = 0;
    std::uint64_t emergencies = 0;
    bool operator==(const Seen&) const = default;
  };
  Seen read(std::size_t i) const;

  slave::Chain& chain_;
  std::vector<Seen> seen_;
};

}  // namespace ecat::control
