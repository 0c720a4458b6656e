#include "pdi_host/pdi_host.hpp"

#include <fcntl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <fmt/format.h>

#include "common/unix_listener.hpp"

#include "pdi_spi/emulated_et1100_spi.hpp"
#include "pdi_spi/emulated_lan9252.hpp"

namespace ecat::pdi_host {
namespace {

constexpr std::size_t kReadChunk = 16384;

std::string errno_text() { return std::strerror(errno); }

// The owner's firmware only (mode 0600).
Expected<int, std::string> listen_unix(const std::string& path) {
  return listen_unix_owner_only(path, "--pdi-host");
}

std::unique_ptr<pdi_spi::EmulatedChip> make_chip(esc::Esc& esc, PdiChip kind) {
  if (kind == PdiChip::Lan9252) return std::make_unique<pdi_spi::EmulatedLan9252>(esc);
  if (kind == PdiChip::Et1100Spi) return std::make_unique<pdi_spi::EmulatedEt1100Spi>(esc);
  return nullptr;
}

}  // namespace

Expected<std::unique_ptr<PdiHost>, std::string> PdiHost::open(const std::string& path, esc::Esc& esc, PdiChip chip,
                                                              const Clock& clock, Log log) {
  auto fd = listen_unix(path);
  if (!fd) return fail(fd.error());
  return std::unique_ptr<PdiHost>(new PdiHost(*fd, path, esc, chip, clock, std::move(log)));
}

PdiHost::PdiHost(int listen_fd, std::string path, esc::Esc& esc, PdiChip kind, const Clock& clock, Log log)
    : listen_fd_(listen_fd),
      path_(std::move(path)),
      esc_(esc),
      chip_(make_chip(esc, kind)),
      session_(esc, kind, chip_.get(), clock),
      log_(std::move(log)) {
  esc_.dc().set_observer(this);
}

PdiHost::~PdiHost() {
  esc_.dc().set_observer(nullptr);
  if (client_ >= 0) ::close(client_);
  ::close(listen_fd_);
  ::unlink(path_.c_str());
}

std::size_t PdiHost::fds(pollfd* out, std::size_t room) const noexcept {
  std::size_t n = 0;
  if (n < room) out[n++] = pollfd{listen_fd_, POLLIN, 0};
  if (client_ >= 0 && n < room) out[n++] = pollfd{client_, POLLIN, 0};
  return n;
}

void PdiHost::on_sync(unsigned signal, bool level, Nanoseconds /*t*/) noexcept {
  if (level) sync_ = static_cast<std::uint8_t>(sync_ | (signal == 0 ? ECAT_PDI_SYNC0 : ECAT_PDI_SYNC1));
}

void PdiHost::drop(const std::string& reason) {
  if (log_) log_(fmt::format("pdi-host: firmware disconnected: {}", reason));
  ::close(client_);
  client_ = -1;
  in_.clear();
  out_.clear();
}

void PdiHost::accept_firmware() {
  for (;;) {
    const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) return;
    if (client_ >= 0) {
      ++stats_.refused;
      if (log_) log_("pdi-host: a second firmware was refused: one is attached");
      ::close(fd);
      continue;
    }
    client_ = fd;
    ++stats_.connections;
    if (log_) log_(fmt::format("pdi-host: firmware attached on {}", path_));
    sync_ = 0;
    session_.greet(out_);
  }
}

bool PdiHost::read_firmware() {
  // Never more than one whole message kept back: a flood waits in the socket.
  while (in_.size() < PdiSession::kMaxMessage) {
    const std::size_t start = in_.size();
    in_.resize(start + kReadChunk);
    const ssize_t n = ::recv(client_, in_.data() + start, kReadChunk, 0);
    in_.resize(start + static_cast<std::size_t>(std::max<ssize_t>(n, 0)));
    if (n > 0) continue;
    if (n == 0) {
      drop("the firmware closed its socket");
      return false;
    }
    if (errno == EAGAIN || errno == EWOULDBLOCK) return true;
    if (errno == EINTR) continue;
    // A Unix socket closed with data unread in it resets the connection.
    if (errno == ECONNRESET) {
      drop("the firmware closed its socket with replies unread");
      return false;
    }
    drop(fmt::format("read: {}", errno_text()));
    return false;
  }
  return true;
}

bool PdiHost::flush() {
  std::size_t sent = 0;
  while (sent < out_.size()) {
    const ssize_t n = ::send(client_, out_.data() + sent, out_.size() - sent, MSG_NOSIGNAL);
    if (n > 0) {
      sent += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
    out_.erase(out_.begin(), out_.begin() + static_cast<std::ptrdiff_t>(sent));
    drop(fmt::format("write: {}", errno_text()));
    return false;
  }
  out_.erase(out_.begin(), out_.begin() + static_cast<std::ptrdiff_t>(sent));
  if (out_.size() > kMaxPendingOut) {
    ++stats_.dropped;
    drop(fmt::format("{} bytes of replies unread: the firmware does not read its socket", out_.size()));
    return false;
  }
  return true;
}

void PdiHost::service(Nanoseconds now) {
  accept_firmware();
  if (client_ < 0) return;
  if (!read_firmware()) return;
  auto handled = session_.handle(in_, out_, kMessagesPerService);
  if (!handled) {
    ++stats_.dropped;
    (void)flush();  // the replies to the requests before the bad one
    if (client_ >= 0) drop(handled.error());
    return;
  }
  stats_.messages += *handled;
  notify(now);
}

void PdiHost::notify(Nanoseconds /*now*/) {
  if (client_ < 0) {
    sync_ = 0;
    return;
  }
  if (session_.notify(out_, sync_)) ++stats_.notifications;
  sync_ = 0;
  if (!out_.empty()) (void)flush();
}

}  // namespace ecat::pdi_host
