// One-line texts for the master library's error values, for messages at the
// edge of the program.
#pragma once

#include <string>

#include <fmt/format.h>

#include "master/master_error.hpp"
#include "master/sdo_abort.hpp"

namespace ecat::app {

inline std::string error_text(master::MasterError e) { return std::string(master::describe(e)); }

inline std::string error_text(const master::SdoError& e) {
  if (e.from_slave) return fmt::format("SDO abort 0x{:08X}", static_cast<std::uint32_t>(e.code));
  return std::string(master::describe(e.cause));
}

}  // namespace ecat::app
