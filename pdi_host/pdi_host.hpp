// ecat-slave --pdi-host PATH: the PDI of one emulated ESC offered to a
// firmware in another process over a Unix stream socket (mode 0600), one
// firmware at a time (docs/pdi-host.md). Thread-free and non-blocking: the
// owner's live loop waits on fds() with its transport, then calls
// service(now) - accept, read, answer through the PdiSession, write - and
// after every frame notify(now), which sends the interrupt lines when they
// changed. A firmware that is slow, stops or dies costs the network
// nothing: the ESC goes on as silicon with a silent µC (its PDI watchdog
// expires), and the next firmware may attach. A malformed message, a
// second firmware, or one that reads no replies is disconnected with the
// reason logged.
#pragma once

#include <poll.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/clock.hpp"
#include "common/expected.hpp"
#include "esc/dc/dc_unit.hpp"
#include "esc/esc.hpp"
#include "pdi_host/pdi_session.hpp"
#include "pdi_spi/emulated_chip.hpp"

namespace ecat::pdi_host {

struct PdiHostStats {
  std::uint64_t connections = 0;  // firmware attached
  std::uint64_t refused = 0;      // closed at once: another firmware was attached
  std::uint64_t dropped = 0;      // closed by the host (bad message, no reader)
  std::uint64_t messages = 0;     // requests answered
  std::uint64_t notifications = 0;
};

class PdiHost final : private esc::DcObserver {
 public:
  // Requests answered per service() call: a flooding firmware leaves the
  // rest for the next turn, after the frames that are waiting.
  static constexpr std::size_t kMessagesPerService = 64;
  // Replies and notifications not yet read beyond this: the firmware is
  // dropped (it does not read its socket).
  static constexpr std::size_t kMaxPendingOut = std::size_t{1} << 20;
  using Log = std::function<void(const std::string&)>;

  // Listens on `path` (a stale socket there is replaced, any other file is
  // an error) for a firmware on `esc`'s PDI of kind `chip`. Takes over the
  // ESC's DC observer (SYNC pulses become notifications).
  static Expected<std::unique_ptr<PdiHost>, std::string> open(const std::string& path, esc::Esc& esc, PdiChip chip,
                                                              const Clock& clock, Log log);
  ~PdiHost() override;
  PdiHost(const PdiHost&) = delete;
  PdiHost& operator=(const PdiHost&) = delete;

  // The descriptors to wait on for reading (listening socket, firmware).
  std::size_t fds(pollfd* out, std::size_t room) const noexcept;
  // Work waits that no descriptor will announce (a whole request kept back
  // by kMessagesPerService): the owner must not sleep.
  bool busy() const noexcept { return client_ >= 0 && PdiSession::has_message(in_); }
  void service(Nanoseconds now);
  // Sends the lines if they changed (cheap when they did not).
  void notify(Nanoseconds now);

  bool attached() const noexcept { return client_ >= 0; }
  const PdiHostStats& stats() const noexcept { return stats_; }
  const std::string& path() const noexcept { return path_; }
  // The emulated SPI chip (lan9252 / et1100-spi), null for direct.
  const pdi_spi::EmulatedChip* chip() const noexcept { return chip_.get(); }

 private:
  PdiHost(int listen_fd, std::string path, esc::Esc& esc, PdiChip kind, const Clock& clock, Log log);
  void on_sync(unsigned signal, bool level, Nanoseconds t) noexcept override;
  void accept_firmware();
  bool read_firmware();
  bool flush();
  void drop(const std::string& reason);

  int listen_fd_;
  int client_ = -1;
  std::string path_;
  esc::Esc& esc_;
  std::unique_ptr<pdi_spi::EmulatedChip> chip_;
  PdiSession session_;
  Log log_;
  std::vector<std::uint8_t> in_;
  std::vector<std::uint8_t> out_;
  std::uint8_t sync_ = 0;  // SYNC pulses not yet told
  PdiHostStats stats_;
};

}  // namespace ecat::pdi_host
