// Output files that are either complete or absent (never half-written): each
// file is written to a temporary name in its own directory and flushed;
// only when every file of a run is staged are they renamed into place (rename
// within one directory is atomic on POSIX file systems). Used by ecat-esigen.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "common/expected.hpp"

namespace ecat::esi {

class StagedFiles {
 public:
  StagedFiles() = default;
  StagedFiles(const StagedFiles&) = delete;
  StagedFiles& operator=(const StagedFiles&) = delete;
  ~StagedFiles();  // removes every temporary file not committed

  // Writes `bytes` to a temporary file next to `target`.
  Expected<void, std::string> stage(const std::filesystem::path& target,
                                    std::span<const std::uint8_t> bytes);
  Expected<void, std::string> stage(const std::filesystem::path& target, std::string_view text);
  // Renames every staged file onto its target.
  Expected<void, std::string> commit();

 private:
  struct Staged {
    std::filesystem::path temp;
    std::filesystem::path target;
  };
  std::vector<Staged> staged_;
};

// One file, atomically.
Expected<void, std::string> write_file_atomic(const std::filesystem::path& target,
                                              std::span<const std::uint8_t> bytes);

}  // namespace ecat::esi
