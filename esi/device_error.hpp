// The one error type of the device loader: where (file and line of the
// offending element) and what. Printed as "file:line: message", the form
// compilers use, so editors can jump to it.
#pragma once

#include <string>

namespace ecat::esi {

struct LoadError {
  std::string file;
  int line = 0;  // 1-based; 0 when the error concerns the file as a whole
  std::string message;

  std::string to_string() const {
    if (line > 0) return file + ":" + std::to_string(line) + ": " + message;
    return file + ": " + message;
  }
};

}  // namespace ecat::esi
