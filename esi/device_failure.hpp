// Inside the loader a failed check throws LoadFailure; the public functions
// of esi/device_loader.hpp catch it and return it as an error value. Kept to
// the XML edge of the program (STYLE lesson 6).
#pragma once

#include <string>

#include "esi/device_error.hpp"
#include "esi/device_spec.hpp"

namespace ecat::esi {

struct LoadFailure {
  LoadError error;
};

[[noreturn]] inline void fail_at(const Where& where, std::string message) {
  throw LoadFailure{LoadError{where.file, where.line, std::move(message)}};
}

}  // namespace ecat::esi
