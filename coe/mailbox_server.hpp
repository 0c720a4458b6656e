// The slave side of the EtherCAT mailbox (ETG.1000.4 §5.6, ETG.1000.6 §5.6;
// shared/spec/coe-mailbox.md §1-3, esc-registers.md §7): requests arrive in
// SM0 (write mailbox), replies leave through SM1 (read mailbox), all through
// the PDI. poll() reads the AL status (0x0130), the AL event request (0x0220)
// and the SM0/SM1 registers, and
//  - answers a repeat request (SM1 activate bit 1 toggled by the master) by
//    writing the lost reply again (or keeping it, when SM1 still holds it
//    unread) and toggling the repeat ack (SM1 PDI control bit 1);
//  - moves the next queued reply into SM1 when it is empty;
//  - reads a full SM0, checks the header and hands the payload to the
//    service registered for its type; a request with the same non-zero
//    counter as the previous one is a repeat: dropped, neither executed
//    nor answered again (ETG.1000.4 mailbox counter; a lost reply is
//    recovered by the SM1 repeat request below).
// Replies wait in a fixed-capacity FIFO; while it is full SM0 is not read,
// so the master's next write is refused by the ESC instead of a reply being
// dropped. Unsolicited messages (emergencies) wait in their own FIFO and go
// out only when no request is waiting for its reply and no segmented
// transfer is in progress, so a master never finds one in place of a reply. The mailbox is open in PreOp, SafeOp and Op (and Bootstrap for
// services that say so).
// Every reply to a request (mailbox error replies and SDO information
// fragments included) carries the request's Address and priority, channel 0
// (ETG.1000.4 §5.6, ETG.8200: a gateway matches replies on the address);
// unsolicited messages carry Address 0, priority 0 (docs/coe.md "Mailbox
// header of replies").
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "coe/mailbox_header.hpp"
#include "coe/mailbox_queue.hpp"
#include "coe/mailbox_service.hpp"
#include "coe/sm_bits.hpp"
#include "common/clock.hpp"
#include "common/expected.hpp"
#include "esc/pdi.hpp"
#include "od/access.hpp"

namespace ecat::coe {

class MailboxServer {
 public:
  static constexpr std::size_t kMaxServices = 4;
  static constexpr std::size_t kDefaultQueueCapacity = 8;
  // Largest unsolicited payload send() takes: a CoE emergency, CoE header +
  // 8 bytes (ETG.1000.6 §5.6.4). The unsolicited queue's slots are this
  // size + the mailbox header, not a whole mailbox (issue 16 item 5).
  static constexpr std::size_t kMaxUnsolicitedPayload = 2 + 8;
  // SM numbers of the mailboxes (ETG.1000.6 §5.6.7.4.1: SM0 write, SM1 read).
  static constexpr unsigned kWriteMailboxSm = 0;
  static constexpr unsigned kReadMailboxSm = 1;

  // `max_mailbox_bytes`: the largest SM0/SM1 length served (header included);
  // buffers are sized from it once.
  MailboxServer(esc::Pdi& pdi, std::size_t max_mailbox_bytes,
                std::size_t queue_capacity = kDefaultQueueCapacity);

  // Start-up only. Returns false when the table is full.
  bool add_service(MailboxService& service) noexcept;
  // Puts `service` in place of the one registered for its type (a test wraps
  // a service in a misbehaving one); the one replaced, null when none was.
  MailboxService* replace_service(MailboxService& service) noexcept;

  void poll(Nanoseconds now) noexcept;

  // Queues an unsolicited message (CoE emergency). Fails with NoMoreMemory
  // when its queue is full or the mailbox is closed (Init), InvalidSize when
  // it does not fit SM1 or is longer than kMaxUnsolicitedPayload.
  Expected<void, MailboxError> send(MailboxType type, ConstBytes payload) noexcept;

  // AL event request bits poll() acts on: SM0 written (a request), SM1 read
  // (room for the next reply). A repeat request shows as an SM activation
  // change (0x0220 bit 4), which the ESM consumes first.
  static constexpr std::uint32_t kEventsHandled = bits::al_event_sm(kWriteMailboxSm) | bits::al_event_sm(kReadMailboxSm);
  // Replies or unsolicited messages wait to go into SM1.
  bool has_output() const noexcept {
    return !queue_.empty() || !unsolicited_.empty() || storm_left_ > 0 || output_service() != nullptr;
  }
  // For a caller that asks has_output() at every pass (slave::Firmware): it
  // may keep the common answer on a cache line of its own that it reads
  // anyway (issue 30 item 1: at 1000 slaves the server's lines were two
  // last-level misses per ask). `*idle` is true exactly while no reply and
  // no unsolicited message waits, no storm is left and no service starts
  // messages itself - then has_output() is false; every public member that
  // changes one of these sets it again. Null: none kept.
  void keep_idle_flag(bool* idle) noexcept {
    idle_flag_ = idle;
    note_idle();
  }

  // Fault injection (slave::FaultCatalogue, docs/faults.md), as SSC's test
  // application offers it. Counter frozen: every reply carries the counter
  // of the one before (ETG.1000.4 §5.6: a master that checks it takes the
  // reply for a repeat). Held: requests are still taken, but no reply or
  // emergency goes into SM1 until released.
  void set_counter_frozen(bool frozen) noexcept { counter_frozen_ = frozen; }
  void set_replies_held(bool held) noexcept { held_ = held; }
  // Test-only breakages (tests/master/conformance_broken_core_test.cpp, the
  // failing-slave proofs of mailbox.counter_repeat / mailbox.repeat_request):
  // counter ignored = a request with the previous counter is executed again;
  // repeat ignored = a repeat request is acknowledged but nothing is resent;
  // error code override = every mailbox error reply, also those of the
  // header checks, carries that code (mailbox.zero_length, length_beyond_sm).
  void set_counter_ignored(bool ignored) noexcept { counter_ignored_ = ignored; }
  void set_error_code_override(std::optional<MailboxError> code) noexcept { error_code_override_ = code; }
  void set_repeat_ignored(bool ignored) noexcept { repeat_ignored_ = ignored; }
  // Error replies: the next `count` requests (0: every one until set again
  // with nullopt) are answered with a mailbox error of that code (ETG.1000.4
  // §5.6, type 0, service 01h) instead of reaching their service.
  void set_error_replies(std::optional<MailboxError> error, std::uint64_t count = 0) noexcept {
    error_reply_ = error;
    error_replies_left_ = count;
  }
  // Reply limit: no reply payload (CoE header and SDO bytes included) longer
  // than `bytes` (0: SM1's room, the normal case); services cut their
  // answers to fit as they do for a small SM1 (SDO uploads go segmented,
  // SDO information fragments). Values below kMinReplyLimit are raised to it.
  static constexpr std::size_t kMinReplyLimit = 16;
  void set_reply_limit(std::size_t bytes) noexcept {
    reply_limit_ = bytes == 0 ? 0 : std::max(bytes, kMinReplyLimit);
  }
  // Storm: `count` copies of one unsolicited message (an emergency), as
  // fast as SM1 is read and the unsolicited rules allow; 0 stops it.
  // Longer than kMaxUnsolicitedPayload: refused (false).
  bool set_unsolicited_storm(MailboxType type, ConstBytes payload, std::uint64_t count) noexcept;
  std::uint64_t storm_left() const noexcept { return storm_left_; }

  // ESM state seen at the last poll.
  od::EsmState state() const noexcept { return state_; }
  bool open() const noexcept { return open_; }
  std::size_t queued() const noexcept { return queue_.size() + unsolicited_.size(); }

 private:
  struct SmRegs {
    std::uint16_t start = 0;
    std::uint16_t length = 0;
    std::uint8_t status = 0;
    std::uint8_t activate = 0;
    std::uint8_t pdi_control = 0;
  };
  void poll_once() noexcept;
  void note_idle() noexcept {
    if (idle_flag_ != nullptr) {
      *idle_flag_ = queue_.empty() && unsolicited_.empty() && storm_left_ == 0 && streamer_count_ == 0;
    }
  }
  SmRegs read_sm(unsigned n) noexcept;
  bool usable(const SmRegs& sm) const noexcept;
  void close() noexcept;
  void handle_repeat_request(const SmRegs& sm1) noexcept;
  bool deliver(const SmRegs& sm1, bool unsolicited_allowed) noexcept;
  bool busy() const noexcept;
  std::size_t next_fragment(int slot, std::uint16_t sm1_length) noexcept;
  MailboxService* output_service() const noexcept;
  std::size_t next_output(int slot, std::uint16_t sm1_length, MailboxService& service) noexcept;
  void write_sm1(const SmRegs& sm1, ConstBytes frame) noexcept;
  void receive(const SmRegs& sm0) noexcept;
  void dispatch(const MailboxHeader& header, ConstBytes payload) noexcept;
  void queue_reply(MailboxType type, std::size_t payload_length) noexcept;
  MailboxHeader reply_header(MailboxType type, std::size_t payload_length, const MailboxHeader& to) noexcept;
  void queue_error(MailboxError error) noexcept;
  void refill_storm() noexcept;
  // The payload room of a reply: SM1's, or less under a reply limit.
  std::size_t reply_room() const noexcept {
    const std::size_t room = sm1_length_ - MailboxHeader::kSize;
    return reply_limit_ == 0 ? room : std::min(room, reply_limit_);
  }
  MailboxService* find(std::uint8_t type) const noexcept;

  esc::Pdi& pdi_;
  std::size_t max_bytes_;
  // What has_output() reads, together (it runs at every firmware poll, and
  // at 1000 slaves every line it touches is a last-level miss).
  std::uint32_t streamer_count_ = 0;
  std::uint32_t service_count_ = 0;  // here, not after services_: the server keeps its size with idle_flag_
  std::uint64_t storm_left_ = 0;
  MailboxQueue queue_;        // replies, in request order
  MailboxQueue unsolicited_;  // emergencies, sent when no request waits for a reply
  // The services that start messages themselves (EoE), polled on every
  // deliver; none for most devices: one compare per poll.
  std::array<MailboxService*, kMaxServices> streamers_{};
  std::array<MailboxService*, kMaxServices> services_{};
  bool* idle_flag_ = nullptr;  // keep_idle_flag
  MailboxService* continuing_ = nullptr;  // service with more replies to give
  MailboxHeader request_header_;          // of the request being answered: its address and priority
  MailboxHeader continuing_header_;       // of the request continuing_ answers

  od::EsmState state_ = od::EsmState::Init;
  bool open_ = false;
  std::uint8_t last_request_counter_ = 0;
  std::uint8_t reply_counter_ = 0;
  bool counter_frozen_ = false;
  bool held_ = false;
  bool counter_ignored_ = false;
  bool repeat_ignored_ = false;
  std::optional<MailboxError> error_code_override_;
  std::optional<MailboxError> error_reply_;
  std::uint64_t error_replies_left_ = 0;  // 0 with error_reply_: until cleared
  std::size_t reply_limit_ = 0;
  MailboxType storm_type_ = MailboxType::CoE;
  std::array<std::uint8_t, kMaxUnsolicitedPayload> storm_payload_{};
  std::size_t storm_size_ = 0;
  std::uint16_t sm0_length_ = 0;
  std::uint16_t sm1_length_ = 0;

  std::vector<std::uint8_t> request_;     // SM0 image
  std::vector<std::uint8_t> reply_;       // reply being built
  std::vector<std::uint8_t> sm1_image_;   // what is written to SM1 (padded)
  // The last two frames written into SM1, for the repeat protocol.
  std::vector<std::uint8_t> written_[2];
  std::size_t written_length_[2] = {0, 0};
  bool have_written_[2] = {false, false};
  int newest_ = 0;  // index into written_ of the frame written last
  // A request was taken after the frame before it was written (so the
  // master had that one): a repeat while SM1 is full keeps SM1's content.
  bool follows_request_[2] = {false, false};
  bool request_since_write_ = false;
  bool reply_went_last_ = false;  // the last message in SM1 was a reply (fair turns with service output)
};

}  // namespace ecat::coe
