// The SII STRINGS category's index space (ETG.2010; sii-eeprom.md §3.1):
// strings are numbered from 1, index 0 means "no string". Equal strings share
// one index; a string longer than 255 bytes is cut to 255; once 255 strings
// exist, further ones get index 0 (documented in docs/esi-sii.md).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "esi/sii_layout.hpp"

namespace ecat::esi {

class SiiStringTable {
 public:
  std::uint8_t add(std::string_view s) {
    if (s.empty()) return 0;
    s = s.substr(0, sii::kMaxStringLength);
    for (std::size_t i = 0; i < strings_.size(); ++i) {
      if (strings_[i] == s) return static_cast<std::uint8_t>(i + 1);
    }
    if (strings_.size() >= sii::kMaxStrings) return 0;
    strings_.emplace_back(s);
    return static_cast<std::uint8_t>(strings_.size());
  }
  std::vector<std::string> take() { return std::move(strings_); }

 private:
  std::vector<std::string> strings_;
};

}  // namespace ecat::esi
