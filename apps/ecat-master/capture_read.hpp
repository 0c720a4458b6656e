// The reading half of --capture (apps/ecat-master/capture.hpp): what one
// slave says about itself, into esi::CaptureInput. Only reads: FPRD of the
// ESC registers, the SII read interface, and CoE mailbox requests (SDO
// information and SDO uploads) once the slave is in PreOp.
#pragma once

#include <string>
#include <vector>

#include "common/expected.hpp"
#include "esi/capture_model.hpp"
#include "master/master.hpp"

namespace ecat::app {

// Registers 0x0000-0x000F and every byte of the SII EEPROM (its size word
// says how many); an error only when neither can be read.
Expected<void, std::string> read_slave_memory(master::Master& master, std::size_t slave, esi::CaptureInput& in);

// The dictionary through SDO information, every entry readable in PreOp
// uploaded. Needs the slave in PreOp with its mailbox set up. One note per
// item that could not be read; in.dictionary_read says whether the OD list
// came back.
void read_dictionary(master::Master& master, std::size_t slave, esi::CaptureInput& in, std::vector<std::string>& notes);

}  // namespace ecat::app
