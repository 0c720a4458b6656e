// Where in a text file something is: the 1-based line and, where the line
// alone does not say which element is meant (a configurator export written on
// one line, several elements on a line), the 1-based byte column of the
// element's '<'. Printed "12" or "1:4711", the forms compilers and editors
// read after "file:" (docs/twins.md "Positions in vendor files").
//
// A SourcePos is made from a line number implicitly and reads as its line
// number where an int is wanted (comparisons, "has a position" tests), so
// code that only knows lines keeps working; printing goes through
// to_string() or fmt, which add the column.
#pragma once

#include <string>

#include <fmt/format.h>

namespace ecat {

struct SourcePos {
  int line = 0;    // 1-based; 0: no position
  int column = 0;  // 1-based byte column; 0: the line says enough

  constexpr SourcePos() noexcept = default;
  constexpr SourcePos(int l) noexcept : line(l) {}  // NOLINT(google-explicit-constructor): a line alone
  constexpr SourcePos(int l, int c) noexcept : line(l), column(c) {}
  constexpr operator int() const noexcept { return line; }  // NOLINT(google-explicit-constructor)

  std::string to_string() const {
    return column > 0 ? std::to_string(line) + ":" + std::to_string(column) : std::to_string(line);
  }
};

}  // namespace ecat

template <>
struct fmt::formatter<ecat::SourcePos> : fmt::formatter<std::string> {
  template <typename Context>
  auto format(const ecat::SourcePos& p, Context& ctx) const {
    return fmt::formatter<std::string>::format(p.to_string(), ctx);
  }
};
