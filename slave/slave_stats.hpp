// Counters that ecat-slave prints on SIGUSR1 / --stats.
#pragma once

#include <cstdint>

#include "esc/al_status_code.hpp"

namespace ecat::slave {

struct SlaveStatus {
  esc::AlState state = esc::AlState::Init;
  bool error = false;
  esc::AlStatusCode code = esc::AlStatusCode::NoError;
  std::uint64_t application_cycles = 0;
  std::uint64_t watchdog_expiries = 0;
  std::uint32_t sync_errors = 0;  // 1C32h:0Bh SM-event-missed counter
  std::uint64_t firmware_polls = 0;  // passes of the firmware (IRQ, deadline or Chain::poll)
};

struct ChainStats {
  std::uint64_t frames_received = 0;   // handed to process_frame
  std::uint64_t frames_returned = 0;   // processed and sent back
  std::uint64_t frames_malformed = 0;  // dropped as malformed (counted in 0x030C, 0x0308+n)
  std::uint64_t frames_lost = 0;       // destroyed in the line (circulating, open port) or back with a bad FCS (a corrupting cable)
  std::uint64_t datagrams = 0;
  std::uint64_t wkc_total = 0;         // sum of returned WKCs
  std::uint64_t frames_stale = 0;      // dropped unprocessed: older than the max frame age when taken (slave/frame_age.hpp)
};

}  // namespace ecat::slave
