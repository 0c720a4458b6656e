// The one error type of the device loader: where (file and line of the
// offending element, with its column where the line alone does not say it:
// common/source_pos.hpp) and what. Printed as "file:line: message" or
// "file:line:column: message", the forms compilers use, so editors can jump
// to it.
#pragma once

#include <string>

#include "common/source_pos.hpp"

namespace ecat::esi {

struct LoadError {
  std::string file;
  SourcePos line;  // 1-based; 0 when the error concerns the file as a whole
  std::string message;

  std::string to_string() const {
    if (line > 0) return file + ":" + line.to_string() + ": " + message;
    return file + ": " + message;
  }
};

}  // namespace ecat::esi
