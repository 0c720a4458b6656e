// What the page redraws from (issue 27): one JSON text built on the loop's
// tick, a few times a second and only while a page is connected. Its content
// is the control interface's own - "network" (control/network_view.hpp),
// "faults", "time" - and for CiA 402 drives the objects the plots show, so
// the page and a Python client see the same data. The process data of the
// slave the page shows is its own "pdo" request (one slave, not all of them
// each time).
//
// Cost (issue 27 item 6: the cyclic path within 2 % with a page open): the
// loop pays for the snapshot, so what does not change is not built again.
// Each slave's view is kept as JSON text with a fingerprint of what it is
// made of (the ESC registers it reads, the sync-error counter, the ports'
// presence and cables); a slave whose fingerprint is unchanged costs a
// compare and a copy of its text. Only its application-cycle counter, which
// moves every cycle, and the drives' values are written each time, as
// numbers straight into the text.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ecat::control {
class RequestHandler;
}
namespace ecat::slave {
struct ChainStats;
class CycleTiming;
}

namespace ecat::web {

class LiveSnapshot {
 public:
  explicit LiveSnapshot(control::RequestHandler& handler) : handler_(handler) {}

  // {"drives": [{"slave", objects..}], "faults": [..],
  //  "network": {"frames": .., "slaves": [..]}, "time_ns": ..} as JSON text;
  // valid until the next take().
  const std::string& take();

  // Slave views built afresh by the takes so far (the rest were copied).
  std::uint64_t views_built() const noexcept { return views_built_; }

  // The ESC register ranges a slave's view reads (network_view.cpp).
  static constexpr std::size_t kRegisterBytes = 36;
  // Per port: present, peer kind, peer slave (2 bytes), peer port.
  static constexpr std::size_t kPortBytes = 5;
  static constexpr std::size_t kFingerprintSize = kRegisterBytes + 4 + 4 * kPortBytes;
  using Fingerprint = std::array<std::uint8_t, kFingerprintSize>;

 private:
  struct SlaveText {
    Fingerprint fingerprint{};
    bool valid = false;
    std::string body;  // the view without "application_cycles" and its opening brace
  };

  // Which slaves have a statusword 6041h (found on the first take).
  const std::vector<bool>& drives(std::size_t slaves);
  Fingerprint fingerprint(std::size_t slave) const;
  void append_frames(const slave::ChainStats& stats, const slave::CycleTiming& cycles);
  void append_slaves();
  void append_drives(const std::vector<bool>& is_drive);

  control::RequestHandler& handler_;
  std::optional<std::vector<bool>> drives_;
  std::vector<SlaveText> slaves_;
  std::string text_;
  std::uint64_t views_built_ = 0;
};

}  // namespace ecat::web
