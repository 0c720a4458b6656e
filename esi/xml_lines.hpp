// Byte offset -> position (line, and column where needed) for a text buffer.
// pugixml reports where a node or a parse error is as a byte offset; error
// messages want "file:line" or, where other elements start before it on its line
// (a configurator export written on one line), "file:line:column"
// (common/source_pos.hpp, docs/twins.md "Positions in vendor files").
#pragma once

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <string_view>
#include <vector>

#include "common/source_pos.hpp"

namespace ecat::esi {

class LineIndex {
 public:
  // A line ends at LF, at CR LF and at a CR alone: XML 1.0 §2.11 reads all
  // three as one line end (Lichuan's LC10E ESI has CR-only line ends). Per
  // line the offset of its first start tag ('<' and a name's first
  // character) is kept.
  explicit LineIndex(std::string_view text) {
    std::size_t first = kNone;
    for (std::size_t i = 0; i < text.size(); ++i) {
      const char c = text[i];
      if (c == '<' && first == kNone && i + 1 < text.size() && starts_name(text[i + 1])) first = i;
      const bool lone_cr = c == '\r' && (i + 1 == text.size() || text[i + 1] != '\n');
      if (c == '\n' || lone_cr) {
        first_tag_.push_back(first);
        first = kNone;
        line_starts_.push_back(i + 1);
      }
    }
    first_tag_.push_back(first);
  }

  // 1-based line of `offset`; 0 for an unknown (negative) offset.
  int line_of(std::ptrdiff_t offset) const noexcept {
    if (offset < 0) return 0;
    auto it = std::upper_bound(line_starts_.begin(), line_starts_.end(),
                               static_cast<std::size_t>(offset));
    return static_cast<int>(it - line_starts_.begin());
  }

  // The line of `offset`, with the 1-based byte column when something else
  // starts on that line before it: the first element of a line is named by
  // the line alone (messages keep the plain "file:line" form, as for every
  // pretty-printed file); anything after it on the same line (the rest of a
  // one-line configurator export, <Entry><Index>...) gets its column.
  SourcePos position_of(std::ptrdiff_t offset) const noexcept {
    const int line = line_of(offset);
    if (line == 0) return SourcePos{};
    const auto at = static_cast<std::size_t>(offset);
    const std::size_t first = first_tag_[static_cast<std::size_t>(line - 1)];
    if (first == kNone || at <= first) return SourcePos{line};
    return SourcePos{line, static_cast<int>(at - line_starts_[static_cast<std::size_t>(line - 1)]) + 1};
  }

 private:
  static bool starts_name(char c) noexcept {
    return std::isalpha(static_cast<unsigned char>(c)) || c == '_' || c == ':';
  }

  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  std::vector<std::size_t> line_starts_{0};
  std::vector<std::size_t> first_tag_;  // per line: offset of its first start tag, or kNone
};

}  // namespace ecat::esi
