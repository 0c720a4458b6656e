// Byte offset -> line number for a text buffer. pugixml reports where a node
// or a parse error is as a byte offset; error messages want lines.
#pragma once

#include <algorithm>
#include <cstddef>
#include <string_view>
#include <vector>

namespace ecat::esi {

class LineIndex {
 public:
  // A line ends at LF, at CR LF and at a CR alone: XML 1.0 §2.11 reads all
  // three as one line end (Lichuan's LC10E ESI has CR-only line ends).
  explicit LineIndex(std::string_view text) {
    for (std::size_t i = 0; i < text.size(); ++i) {
      const bool lone_cr = text[i] == '\r' && (i + 1 == text.size() || text[i + 1] != '\n');
      if (text[i] == '\n' || lone_cr) line_starts_.push_back(i + 1);
    }
  }

  // 1-based line of `offset`; 0 for an unknown (negative) offset.
  int line_of(std::ptrdiff_t offset) const noexcept {
    if (offset < 0) return 0;
    auto it = std::upper_bound(line_starts_.begin(), line_starts_.end(),
                               static_cast<std::size_t>(offset));
    return static_cast<int>(it - line_starts_.begin());
  }

 private:
  std::vector<std::size_t> line_starts_{0};
};

}  // namespace ecat::esi
