// The lines `ecat-master --topology` / `--scan` print: one per slave, its
// parent (1-based like every slave number ecat-master prints, or "master"),
// the parent's port it hangs on, its active ports and entry port, and, once
// DC is set up, the propagation delay written to 0x0928.
#pragma once

#include <string>

#include "master/master.hpp"

namespace ecat::app {

// "slave 3 station 0x1003 parent 1 port 2 ports 0,1,2,3 entry 0" per slave;
// "... open 1" lists active ports with no slave behind (a ring's return port);
// with `with_dc` each DC slave's line ends in "delay 690 ns".
std::string topology_report(const master::Master& master, bool with_dc);

}  // namespace ecat::app
