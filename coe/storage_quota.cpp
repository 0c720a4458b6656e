#include "coe/storage_quota.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <system_error>

namespace ecat::coe {

bool StorageQuota::count_existing(const std::filesystem::path& root) noexcept {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(root, ec)) return !ec;
  try {
    for (fs::recursive_directory_iterator it(root, fs::directory_options::none, ec), end; !ec && it != end;
         it.increment(ec)) {
      std::error_code e;
      const fs::file_status st = it->symlink_status(e);
      if (e || !fs::is_regular_file(st)) continue;
      const std::uintmax_t size = it->file_size(e);
      if (e) continue;
      bytes_ += size;
      ++files_;
    }
  } catch (...) {
    return false;
  }
  return !ec;
}

bool StorageQuota::charge_file() noexcept {
  if (files_ >= limits_.max_files) return false;
  ++files_;
  return true;
}

bool StorageQuota::charge_bytes(std::uint64_t bytes) noexcept {
  if (bytes > limits_.max_bytes || bytes_ > limits_.max_bytes - bytes) return false;
  bytes_ += bytes;
  return true;
}

void StorageQuota::release_bytes(std::uint64_t bytes) noexcept { bytes_ -= std::min(bytes, bytes_); }

void StorageQuota::release_file(std::uint64_t bytes) noexcept {
  release_bytes(bytes);
  if (files_ > 0) --files_;
}

std::optional<std::uint64_t> StorageQuota::regular_file_size(const std::string& path) noexcept {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return std::nullopt;
  return static_cast<std::uint64_t>(st.st_size);
}

}  // namespace ecat::coe
