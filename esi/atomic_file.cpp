#include "esi/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include <fmt/format.h>

namespace ecat::esi {
namespace {

constexpr mode_t kFileMode = 0666;  // before the umask, as open(2) would create it

std::string why(const std::filesystem::path& p, const char* what) {
  return fmt::format("{}: {}: {}", p.string(), what, std::strerror(errno));
}

}  // namespace

StagedFiles::~StagedFiles() {
  for (const auto& s : staged_) ::unlink(s.temp.c_str());
}

Expected<void, std::string> StagedFiles::stage(const std::filesystem::path& target,
                                               std::string_view text) {
  return stage(target, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

Expected<void, std::string> StagedFiles::stage(const std::filesystem::path& target,
                                               std::span<const std::uint8_t> bytes) {
  const auto dir = target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
  std::string name = (dir / ("." + target.filename().string() + ".tmp-XXXXXX")).string();
  const int fd = ::mkstemp(name.data());
  if (fd < 0) return fail(why(target, "cannot create a temporary file"));
  staged_.push_back({name, target});
  const mode_t mask = ::umask(0);
  ::umask(mask);
  if (::fchmod(fd, kFileMode & ~mask) != 0) {
    ::close(fd);
    return fail(why(target, "cannot set permissions"));
  }
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      ::close(fd);
      return fail(why(target, "cannot write"));
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    ::close(fd);
    return fail(why(target, "cannot flush"));
  }
  if (::close(fd) != 0) return fail(why(target, "cannot close"));
  return {};
}

Expected<void, std::string> StagedFiles::commit() {
  while (!staged_.empty()) {
    const auto& s = staged_.front();
    if (::rename(s.temp.c_str(), s.target.c_str()) != 0) return fail(why(s.target, "cannot rename"));
    staged_.erase(staged_.begin());
  }
  return {};
}

Expected<void, std::string> write_file_atomic(const std::filesystem::path& target,
                                              std::span<const std::uint8_t> bytes) {
  StagedFiles files;
  if (auto ok = files.stage(target, bytes); !ok) return ok;
  return files.commit();
}

}  // namespace ecat::esi
