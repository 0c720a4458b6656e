// The Ethernet side of an EoE slave bridged to a Linux TAP interface
// (ecat-slave --eoe-tap NAME; docs/eoe.md "TAP bridge"): frames the master
// sends over EoE are written to the TAP, so the host's stack sees them
// arrive on NAME; frames the host sends out of NAME are read (service(),
// non-blocking) and handed to EoeServer::transmit toward the master.
// /dev/net/tun with IFF_TAP | IFF_NO_PI: one whole Ethernet frame per
// read/write, no packet-information prefix. Needs CAP_NET_ADMIN to create
// the interface. A TAP that fails (deleted, I/O errors) is closed and
// counted; the slave and its mailbox go on, EoE frames are then dropped.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include "coe/eoe_server.hpp"
#include "common/expected.hpp"

namespace ecat::slave {

class EoeTap final : public coe::EthernetPort {
 public:
  struct Stats {
    std::uint64_t to_host = 0;     // frames written to the TAP
    std::uint64_t from_host = 0;   // frames read from the TAP and queued for the master
    std::uint64_t write_errors = 0;
    std::uint64_t read_errors = 0;
    std::uint64_t refused = 0;     // EoeServer::transmit said no (ring full, filter, size)
  };

  // Creates (or attaches to) TAP `name` and makes it the server's Ethernet side.
  static Expected<std::unique_ptr<EoeTap>, std::string> open(const std::string& name, coe::EoeServer& server);
  ~EoeTap() override;
  EoeTap(const EoeTap&) = delete;
  EoeTap& operator=(const EoeTap&) = delete;

  void receive(ConstBytes frame) noexcept override;
  // Reads the frames waiting on the TAP (at most `max_frames`) into the
  // server; returns how many were queued.
  std::size_t service(std::size_t max_frames = coe::eoe::kTxFrames) noexcept;
  bool is_open() const noexcept { return fd_ >= 0; }
  int fd() const noexcept { return fd_; }
  const std::string& name() const noexcept { return name_; }
  const Stats& stats() const noexcept { return stats_; }

 private:
  EoeTap(int fd, std::string name, coe::EoeServer& server) : fd_(fd), name_(std::move(name)), server_(server) {}
  void close_tap() noexcept;

  int fd_ = -1;
  std::string name_;
  coe::EoeServer& server_;
  Stats stats_;
  std::array<std::uint8_t, 2048> buffer_{};  // a read longer than kMaxFrame is refused by transmit
};

}  // namespace ecat::slave
