// File access over EtherCAT (mailbox type 4, ETG.1000.5/6 §5.3.2 FoE;
// shared/spec/coe-mailbox.md §10): read (RRQ -> DATA/ACK ...) and write
// (WRQ -> ACK(0), DATA(k) -> ACK(k) ...) of files in one configured
// directory. A DATA shorter than the mailbox allows ends the file. Names are
// checked: 1..max_name_length characters of [A-Za-z0-9._-], not starting
// with '.', so no path ever leaves the directory. A written file appears
// under its name only when complete (written as <name>.part, then renamed).
// Offered in PreOp, SafeOp, Op and Bootstrap, when the device lists FoE.
// With a StorageQuota, every file and byte written is charged to it first;
// beyond it the write ends with ERR 0x8003 "disk full" (ETG.1000.5 FoE error
// codes), the partial `<name>.part` is removed and any earlier `<name>` stays.
// With Options::password, a request with another password gets ERR 0x800A.
// With Options::busy_replies = N, a slave whose file is not ready at once:
// each read/write request (past the name and password checks) is answered
// BUSY N times, Done = 0..N-1 of Entire = N (ETG.1000.6 §5.3.2 FoE Busy,
// coe-mailbox.md §10), and served when the master sends it the N+1st time.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

#include "coe/mailbox_service.hpp"
#include "coe/storage_quota.hpp"

namespace ecat::coe {

namespace foe {
inline constexpr std::uint8_t kReadRequest = 1;
inline constexpr std::uint8_t kWriteRequest = 2;
inline constexpr std::uint8_t kData = 3;
inline constexpr std::uint8_t kAck = 4;
inline constexpr std::uint8_t kError = 5;
inline constexpr std::uint8_t kBusy = 6;
inline constexpr std::size_t kHeaderSize = 6;  // opcode, reserved, UINT32
// BUSY: the UINT32 field is Done (UINT16, bytes 2-3) then Entire (UINT16, bytes 4-5).
inline constexpr unsigned kBusyEntireShift = 16;

enum class FoeError : std::uint32_t {
  NotDefined = 0x8000,
  NotFound = 0x8001,
  AccessDenied = 0x8002,
  DiskFull = 0x8003,
  Illegal = 0x8004,
  PacketNumber = 0x8005,
  AlreadyExists = 0x8006,
  NoUser = 0x8007,
  BootstrapOnly = 0x8008,
  NotInBootstrap = 0x8009,
  NoRights = 0x800A,
  ProgramError = 0x800B,
  Checksum = 0x800C,
};
}  // namespace foe

class FoeServer final : public MailboxService {
 public:
  struct Options {
    std::string directory;                      // empty: every request is refused
    std::size_t max_file_bytes = 16u << 20;     // writes beyond: ERR disk full
    std::size_t max_name_length = 64;
    StorageQuota* quota = nullptr;              // shared budget of the state directory; null: none
    // Password every RRQ/WRQ must carry (0: none). Another one is ERR 0x800A
    // "no rights", as SOES answers a file's wrong password (ETG.1000.6 gives
    // RRQ/WRQ a password field but, in what is at hand, no code for it).
    std::uint32_t password = 0;
    // BUSY replies before each RRQ/WRQ is served (0: never busy).
    std::uint16_t busy_replies = 0;
  };

  explicit FoeServer(Options options) : options_(std::move(options)) {}
  ~FoeServer() override { reset(); }
  FoeServer(const FoeServer&) = delete;
  FoeServer& operator=(const FoeServer&) = delete;

  MailboxType type() const noexcept override { return MailboxType::FoE; }
  bool active_in(od::EsmState state) const noexcept override {
    return state == od::EsmState::Bootstrap || MailboxService::active_in(state);
  }
  Expected<std::size_t, MailboxError> handle(ConstBytes request, Bytes reply, od::EsmState state) noexcept override;
  void set_sizes(std::size_t request_payload, std::size_t reply_payload) noexcept override {
    request_payload_ = request_payload;
    (void)reply_payload;
  }
  void reset() noexcept override;
  bool busy() const noexcept override { return state_ != State::Idle; }

  bool safe_name(std::string_view name) const noexcept;

 private:
  enum class State : std::uint8_t { Idle, Reading, Writing };

  std::size_t read_request(std::uint32_t password, std::string_view name, Bytes reply) noexcept;
  std::size_t write_request(std::uint32_t password, std::string_view name, Bytes reply) noexcept;
  std::size_t data(std::uint32_t packet, ConstBytes bytes, Bytes reply) noexcept;
  std::size_t ack(std::uint32_t packet, Bytes reply) noexcept;
  std::size_t send_data(Bytes reply) noexcept;
  std::size_t error(Bytes reply, foe::FoeError code) noexcept;
  // A BUSY reply while busy_replies are due, else 0 (serve the request).
  std::size_t busy(Bytes reply) noexcept;
  static std::size_t header(Bytes reply, std::uint8_t opcode, std::uint32_t value) noexcept;

  Options options_;
  State state_ = State::Idle;
  std::FILE* file_ = nullptr;
  std::string path_;       // final name
  std::string temp_path_;  // while writing
  std::uint32_t packet_ = 0;
  std::size_t size_ = 0;
  bool temp_charged_ = false;  // the .part file is charged to the quota, with size_ bytes
  bool last_short_ = false;
  std::size_t request_payload_ = 0;
  std::uint16_t busy_given_ = 0;  // BUSY replies since a request was last served
};

}  // namespace ecat::coe
