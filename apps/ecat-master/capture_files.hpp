// The files of a capture (apps/ecat-master/capture.hpp): names, the device
// file with its notes as an XML comment, the topology in ecat-slave
// --topology's line format (apps/ecat-slave/topology.hpp).
#pragma once

#include <string>
#include <vector>

#include "master/topology.hpp"

namespace ecat::app {

// "<pos>-<name>": position from 1, the device name with every character
// other than [A-Za-z0-9._-] as '-' ("slave" when the SII names none).
std::string capture_base_name(std::size_t position, const std::string& device_name);

// The device XML with the notes as a comment after the XML declaration.
std::string with_notes_comment(const std::string& device_xml, const std::vector<std::string>& notes);

// One `slave` line per slave in position order, named s<pos>, placed at its
// parent's port as the scan found it (port N when it is entered on another
// port than 0). A slave the scan found on the master beyond the first
// (a broken ring's far side) is placed behind the slave before it, with a note.
std::string capture_topology(const std::vector<master::SlaveTopology>& slaves, const std::vector<std::string>& files,
                             std::vector<std::string>& notes);

}  // namespace ecat::app
