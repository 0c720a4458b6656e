// How much a master may write into the state directory (ecat-slave
// --state-dir): FoE files (coe/foe_server.hpp) and stored parameters
// (1010h, coe/parameter_store.hpp) of every slave draw on one budget of bytes
// and of files. EtherCAT has no authentication (docs/security.md): without a
// bound, any peer that reaches the slave could fill the disk, one 16 MiB FoE
// file after the other.
//
// A ledger, not a file system query: count_existing() adds what the
// directory holds at start (regular files, apparent size, symbolic links not
// followed); from then on the writers charge every byte and file before they
// write it and give back what they delete or replace. Temporary files
// (`<name>.part`, `<file>.tmp`) are charged like any other while they exist,
// so replacing a file needs room for both copies until the rename. Files
// changed behind the program's back are seen at the next start. One thread.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace ecat::coe {

class StorageQuota {
 public:
  struct Limits {
    std::uint64_t max_bytes = std::uint64_t{64} << 20;
    std::uint64_t max_files = 1024;
  };

  explicit StorageQuota(Limits limits) noexcept : limits_(limits) {}

  // Adds the regular files under `root` (recursively) to the ledger; a
  // missing directory adds nothing. Returns false when it could not be read.
  bool count_existing(const std::filesystem::path& root) noexcept;

  // Charges one more file / `bytes` more; false (nothing charged) when that
  // would go beyond the limit.
  bool charge_file() noexcept;
  bool charge_bytes(std::uint64_t bytes) noexcept;
  // Gives back one file of `bytes` (deleted or replaced), or bytes alone.
  void release_file(std::uint64_t bytes) noexcept;
  void release_bytes(std::uint64_t bytes) noexcept;
  // Size of the regular file at `path` (symbolic links not followed), if
  // there is one: what a rename over it or an unlink gives back.
  static std::optional<std::uint64_t> regular_file_size(const std::string& path) noexcept;

  std::uint64_t used_bytes() const noexcept { return bytes_; }
  std::uint64_t used_files() const noexcept { return files_; }
  const Limits& limits() const noexcept { return limits_; }

 private:
  Limits limits_;
  std::uint64_t bytes_ = 0;
  std::uint64_t files_ = 0;
};

}  // namespace ecat::coe
