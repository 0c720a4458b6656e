// A listening Unix stream socket only its owner may connect to (mode 0600,
// created so through the umask: there is no moment where others could
// connect), non-blocking and close-on-exec; a socket left at the path by an
// earlier run is replaced, any other file there is an error. Used by the
// control interface (ecat-slave --control) and the PDI host (--pdi-host).
#pragma once

#include <fcntl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "common/expected.hpp"

namespace ecat {

inline constexpr mode_t kOwnerOnlySocketMode = 0600;
inline constexpr mode_t kOwnerOnlySocketUmask = 0177;
inline constexpr int kUnixListenBacklog = 8;

// `option` names the command-line option in error messages ("--control").
inline Expected<int, std::string> listen_unix_owner_only(const std::string& path, std::string_view option) {
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (path.empty() || path.size() >= sizeof(addr.sun_path)) {
    return fail(fmt::format("{} {}: a Unix socket path of 1..{} bytes is needed", option, path,
                            sizeof(addr.sun_path) - 1));
  }
  std::memcpy(addr.sun_path, path.data(), path.size());
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0) {
    if (!S_ISSOCK(st.st_mode)) return fail(fmt::format("{} {}: exists and is not a socket", option, path));
    ::unlink(path.c_str());  // a stale socket of an earlier run
  }
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd < 0) return fail(fmt::format("{} {}: socket: {}", option, path, std::strerror(errno)));
  const mode_t old = ::umask(kOwnerOnlySocketUmask);
  const int bound = ::bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr));
  ::umask(old);
  if (bound != 0 || ::chmod(path.c_str(), kOwnerOnlySocketMode) != 0 || ::listen(fd, kUnixListenBacklog) != 0) {
    const std::string why = std::strerror(errno);
    ::close(fd);
    return fail(fmt::format("{} {}: {}", option, path, why));
  }
  return fd;
}

}  // namespace ecat
