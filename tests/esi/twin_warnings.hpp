// What the twin-repair tests ask of an ESI read: the line a piece of the
// test's ESI text is on, whether a warning names that line and says a given
// thing, all warnings as text for a failure message, and the read itself
// (the description and its warnings).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "esi/esi_reader.hpp"
#include "esi/twin_judge.hpp"

namespace ecat::esi::test {

// The 1-based line of the first `needle` in `text`; -1 when absent.
inline int line_of(const std::string& text, const std::string& needle) {
  const auto at = text.find(needle);
  if (at == std::string::npos) return -1;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

inline std::string all(const std::vector<EsiWarning>& w) {
  std::string s;
  for (const auto& x : w) s += x.to_string("t.xml") + "\n";
  return s;
}

inline bool has_warning(const std::vector<EsiWarning>& w, int line, const std::string& part) {
  return std::any_of(w.begin(), w.end(), [&](const EsiWarning& x) {
    return x.line == line && x.message.find(part) != std::string::npos;
  });
}

inline bool warns_about(const std::vector<EsiWarning>& w, const std::string& part) {
  return std::any_of(w.begin(), w.end(),
                     [&](const EsiWarning& x) { return x.message.find(part) != std::string::npos; });
}

struct Read {
  std::vector<EsiWarning> warnings;
  od::DeviceDescription d;
};

// Reads `text` as the ESI file t.xml; a failure fails the test.
inline Read read(const std::string& text) {
  Read r;
  auto d = read_esi_string(text, "t.xml", {}, &r.warnings);
  EXPECT_TRUE(d) << d.error().to_string();
  if (d) r.d = *d;
  return r;
}

// A corpus file read and judged as a twin: its path and text, the
// description, and its warnings as "SHOWN:line: warning: ..." text.
struct FileRead {
  std::string file, text;
  od::DeviceDescription d;
  std::vector<std::string> warnings;
};

// Reads the ESI at `path` (the warnings name it `shown`); a read or a judge
// that fails fails the test.
inline FileRead read_judged(const std::string& path, const std::string& shown) {
  FileRead r;
  r.file = path;
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  r.text = s.str();
  std::vector<EsiWarning> w;
  auto d = read_esi(path, EsiSelection{}, &w);
  EXPECT_TRUE(d) << d.error().to_string();
  if (d) r.d = *d;
  for (const auto& x : w) r.warnings.push_back(x.to_string(shown));
  auto judged = judge_twin(r.d);
  EXPECT_TRUE(judged) << judged.error();
  return r;
}

}  // namespace ecat::esi::test
