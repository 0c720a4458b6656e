// `ecat-master --capture DIR` (docs/twins.md "Capturing a twin from a live
// network"): scans the segment and writes, per slave, DIR/<pos>-<name>.xml
// (a device file ecat-slave --device loads), DIR/<pos>-<name>.sii.bin (the
// SII image as read, every byte of the EEPROM) and DIR/topology.txt (the
// cabling as found, for ecat-slave --topology). Reads only: besides the
// scan's own writes (station addresses, AL control), each mailbox slave gets
// its SM0/SM1 set up, goes to PreOp for the SDO information and uploads, and
// back to Init. Per-item problems are notes (printed, in the device file as
// an XML comment and in DIR/<pos>-<name>.notes.txt), never a stop.
#pragma once

#include <string>

#include "common/expected.hpp"
#include "master/master.hpp"

namespace ecat::app {

struct CaptureSummary {
  std::size_t slaves = 0;
  std::size_t notes = 0;
};

Expected<CaptureSummary, std::string> capture_network(master::Master& master, const std::string& dir);

}  // namespace ecat::app
