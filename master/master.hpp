// A small EtherCAT master over any Transport, doing the standard start-up
// sequence the way SOEM/IgH/ethercrab do it (shared/spec/masters.md): count
// slaves (BRD 0x0000), assign station addresses (APWR 0x0010), read ESC info
// and the SII, configure the mailbox SMs from the SII, walk the ESM, talk
// CoE through the mailbox (see coe_client.hpp), map process data and run the
// cyclic LRW exchange, and set up distributed clocks. One object holds all
// state (no globals); buffers are sized at set-up, the cyclic exchange does
// not allocate. Time comes from the injected Clock; nothing sleeps — polling
// loops end at a deadline (see PollBudget).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "common/clock.hpp"
#include "common/expected.hpp"
#include "master/datagram_link.hpp"
#include "master/mailbox.hpp"
#include "master/process_image_plan.hpp"
#include "master/master_error.hpp"
#include "master/slave_info.hpp"
#include "transport/transport.hpp"

namespace ecat::master {

class DatagramBatch;

struct MasterConfig {
  LinkConfig link{};
  std::uint16_t first_station_address = 0x1001;  // SOEM: 0x1000 + position + 1
  std::size_t max_slaves = 64;
  Nanoseconds sii_timeout = std::chrono::milliseconds(20);
  Nanoseconds state_timeout = std::chrono::seconds(5);
  Nanoseconds mailbox_timeout = std::chrono::seconds(1);
  // Wait loops end at their timeout; only when the clock does not move at
  // all (a ManualClock nobody advances) do they end after this many polls.
  unsigned max_polls = 5000;
  // Map each mailbox slave's SM1 status byte (0x080D) into the process image
  // with one more FMMU (SOEM, TwinCAT), so mailbox replies can be seen from
  // the cyclic frame (mailbox_reply_flagged) instead of an FPRD per slave.
  bool map_mailbox_status = false;
  // Data bytes per cyclic logical datagram (at most kMaxDatagramData = 1486,
  // SOEM's EC_MAXLRWDATA); a smaller value puts several datagrams in a frame.
  std::size_t max_process_datagram = kMaxDatagramData;
  // scan(): read the SII STRINGS category. Off, its bytes stay zero in
  // SlaveInfo::sii_image (no strings, no device name) and the scan reads about
  // half the words of a typical image (only what configuration needs).
  bool read_sii_strings = true;
};

// Result of one cyclic exchange.
struct CyclicResult {
  std::uint16_t wkc = 0;
  std::uint16_t expected_wkc = 0;
  Nanoseconds round_trip{0};
  Nanoseconds sent_at{0};  // the master's clock just before the frame was sent
  // With DC: the reference clock's system time when the frame passed it
  // (the FRMW 0x0910:8 read-back), if the datagram came back with WKC >= 1.
  std::optional<std::uint64_t> reference_time;
  std::uint16_t frames = 0;           // frames the cycle took
  std::uint16_t datagrams_wrong = 0;  // logical datagrams whose WKC was not their expected one
  bool ok() const noexcept { return wkc == expected_wkc && datagrams_wrong == 0; }
};

struct CyclicStats {
  std::uint64_t cycles = 0;
  std::uint64_t wkc_errors = 0;
  std::uint64_t lost_frames = 0;
  Nanoseconds min_round_trip{0};
  Nanoseconds max_round_trip{0};
  Nanoseconds total_round_trip{0};
  Nanoseconds average_round_trip() const noexcept {
    return cycles == 0 ? Nanoseconds{0} : Nanoseconds{total_round_trip.count() / static_cast<std::int64_t>(cycles)};
  }
};

// A reply read from a slave's read mailbox (SM1).
struct MailboxMessage {
  mbx::Header header;
  std::span<const std::uint8_t> payload;  // valid until the next mailbox call
};

class Master {
 public:
  Master(transport::Transport& transport, const Clock& clock, MasterConfig config = {});

  // --- datagrams and registers ---------------------------------------------------
  DatagramLink& link() noexcept { return link_; }
  const MasterConfig& config() const noexcept { return config_; }
  const Clock& clock() const noexcept { return clock_; }
  // Any command; `data` is sent and replaced by the reply. Returns the WKC.
  Expected<std::uint16_t, MasterError> transact(Command command, std::uint32_t address, Bytes data);
  // FPRD/FPWR to a configured station address; WKC must be 1.
  Expected<void, MasterError> fprd(std::uint16_t station, std::uint16_t reg, Bytes out);
  Expected<void, MasterError> fpwr(std::uint16_t station, std::uint16_t reg, ConstBytes in);
  Expected<std::uint8_t, MasterError> fprd_u8(std::uint16_t station, std::uint16_t reg);
  Expected<std::uint16_t, MasterError> fprd_u16(std::uint16_t station, std::uint16_t reg);
  Expected<std::uint32_t, MasterError> fprd_u32(std::uint16_t station, std::uint16_t reg);
  Expected<void, MasterError> fpwr_u8(std::uint16_t station, std::uint16_t reg, std::uint8_t v);
  Expected<void, MasterError> fpwr_u16(std::uint16_t station, std::uint16_t reg, std::uint16_t v);
  Expected<void, MasterError> fpwr_u32(std::uint16_t station, std::uint16_t reg, std::uint32_t v);
  // Broadcast write; returns the WKC (number of slaves that took it).
  Expected<std::uint16_t, MasterError> bwr(std::uint16_t reg, ConstBytes in);

  // --- scan (masters.md §1.1) -------------------------------------------------------
  // One frame of four BWRs: register and ESC write enable (0x0020, 0x0030 = 1),
  // then register and ESC write protection off (0x0021, 0x0031 = 0). Enables
  // first: ESC write protection also blocks 0x0021. WKCs are not checked.
  Expected<void, MasterError> clear_write_protection();
  // BRD 0x0000: the WKC is the number of slaves.
  Expected<std::size_t, MasterError> count_slaves();
  // Write protection off, Init + ack broadcast, reset FMMUs/SMs/DC activation, SII to ECAT, station
  // addresses, ESC info, DL status, AL status, SII image per slave.
  Expected<std::size_t, MasterError> scan();
  std::size_t slave_count() const noexcept { return slaves_.size(); }
  SlaveInfo& slave(std::size_t i) { return slaves_.at(i); }
  const std::vector<SlaveInfo>& slaves() const noexcept { return slaves_; }

  // --- SII (esc-registers.md §9) --------------------------------------------------
  // One read command at `word_address`; fills 4 or 8 bytes (0x0502 bit 6) into
  // `out` (at least 8 bytes) and returns how many the ESC delivered.
  Expected<std::size_t, MasterError> sii_read(std::uint16_t station, std::uint16_t word_address, Bytes out);
  // The whole image up to and including the 0xFFFF end marker.
  Expected<std::vector<std::uint8_t>, MasterError> read_sii_image(std::uint16_t station);
  // Every slave's image into SlaveInfo::sii_image, the slaves read side by
  // side (same datagrams per slave as read_sii_image, many slaves per frame).
  Expected<void, MasterError> read_sii_images();

  // --- ESM (ETG.1000.6 §6.4; esm-al-codes.md) --------------------------------------
  Expected<AlStatus, MasterError> read_al_status(std::size_t slave);
  // Writes 0x0120 (= state, | 0x10 if ack) and polls 0x0130 until the state is
  // reached without error (success) or the error bit is set (refused: the
  // returned status has error() and the 0x0134 code). Timeout -> StateTimeout.
  Expected<AlStatus, MasterError> request_state(std::size_t slave, AlState state, bool ack = false);
  // Same with a raw 0x0120 value (to test unknown state codes).
  Expected<AlStatus, MasterError> write_al_control(std::size_t slave, std::uint16_t value);
  // Acknowledges a pending error: writes current state | 0x10, polls until ErrInd clears.
  Expected<AlStatus, MasterError> acknowledge_error(std::size_t slave);
  // Every slave; stops at the first failure or refusal (returned as error StateTimeout/refusal code kept per slave).
  Expected<void, MasterError> request_state_all(AlState state);

  // --- mailbox (ETG.1000.4 §5.6; coe-mailbox.md §1-§3) ------------------------------
  // SM0/SM1 from the SII SYNCM category (words 0x18-0x1B, control 0x26/0x22 as fallback).
  Expected<void, MasterError> configure_mailbox(std::size_t slave);
  // configure_mailbox for every slave whose SII has a mailbox, the slaves'
  // datagrams packed into as few frames as fit; returns how many were set up.
  Expected<std::size_t, MasterError> configure_mailboxes();
  // Programs SM n: first disabled (start/length/control are writable only
  // while the SM is off, Section II 0x0800), then the new values.
  Expected<void, MasterError> write_sync_manager(std::size_t slave, unsigned n, std::uint16_t start,
                                                 std::uint16_t length, std::uint8_t control, bool enable);
  // Writes SM0/SM1 exactly as given (for tests of invalid configurations).
  Expected<void, MasterError> write_mailbox_sms(std::size_t slave, const MailboxLayout& layout, bool enable = true);
  // Sends one message (header added, counter rotated 1..7) as one FPWR of the
  // whole SM0 area; retries while the mailbox is full. Returns the counter used.
  Expected<std::uint8_t, MasterError> mailbox_send(std::size_t slave, std::uint8_t type, ConstBytes payload);
  // Same with an explicit counter (0..7), for repeat/counter tests.
  Expected<void, MasterError> mailbox_send_raw(std::size_t slave, std::uint8_t type, std::uint8_t counter,
                                               ConstBytes payload, std::uint16_t length_override = 0xFFFF);
  // Polls SM1 status bit 3 until full, reads the whole SM1 area. A read with
  // WKC 0 after "full" triggers the repeat-request handshake.
  Expected<MailboxMessage, MasterError> mailbox_receive(std::size_t slave, Nanoseconds timeout);
  Expected<bool, MasterError> mailbox_has_reply(std::size_t slave);
  // Repeat request (esc-registers.md §7.2): toggle SM1 activate bit 1, wait for
  // PDI control bit 1 to follow.
  Expected<void, MasterError> mailbox_repeat_request(std::size_t slave);
  // Detail code of the last mailbox error reply (type 0).
  mbx::MailboxErrorCode last_mailbox_error() const noexcept { return last_mailbox_error_; }

  // --- process data (masters.md §1.3) ----------------------------------------------
  // Lays out the image (all outputs, then all inputs, slave order), programs
  // the process-data SMs and their FMMUs: SM2/SM3 (start/control from SII,
  // length from pd.output_bytes/input_bytes, which the caller filled), or
  // every SM in pd.sms when sized per SM (pd.per_sm), one FMMU per run of
  // SMs of a direction that lie back to back.
  Expected<void, MasterError> configure_process_data();
  // Writes one slave's process-data SMs and FMMUs again, as
  // configure_process_data() laid them out (after readdress()).
  Expected<void, MasterError> write_process_data_config(std::size_t slave);
  // Sizes every SII SM of type 3/4 from the SII PDOs assigned to it (a
  // slave without CoE, as SOEM's ecx_map_sii): fills pd.sms, sets pd.per_sm.
  void size_process_data_from_sii(std::size_t slave);
  // The image may need several logical datagrams and frames (more than 1486
  // bytes): process_data_plan() lists them, each with its expected WKC.
  // One LRW per datagram over the image (+ FRMW 0x0910 to the reference clock
  // in the first frame when DC is on). Copies outputs in and inputs out; no
  // allocation. Every datagram's WKC is checked (CyclicResult::datagrams_wrong). When a slave
  // cannot take LRW (0x0008 bit 9, or SII GENERAL flag "not LRW") the frame
  // carries LWR (outputs) + LRD (inputs) instead and the WKC is counted as
  // 2 x LWR + LRD, so the expected value stays the same (SOEM).
  Expected<CyclicResult, MasterError> exchange_process_data();
  std::uint16_t expected_wkc() const noexcept { return expected_wkc_; }
  std::span<const PdDatagram> process_data_plan() const noexcept { return pd_plan_; }
  std::size_t process_data_frames() const noexcept { return pd_frames_; }
  // WKC of logical datagram `i` of the plan in the last cyclic exchange.
  std::uint16_t last_datagram_wkc(std::size_t i) const noexcept;
  // SM1 "mailbox full" (0x080D bit 3) as the last cyclic exchange saw it;
  // false when the status byte is not mapped (MasterConfig::map_mailbox_status).
  bool mailbox_reply_flagged(std::size_t slave) const noexcept;
  Bytes outputs(std::size_t slave);
  ConstBytes inputs(std::size_t slave) const;
  std::span<std::uint8_t> process_image() noexcept { return image_; }
  const CyclicStats& cyclic_stats() const noexcept { return cyclic_stats_; }
  bool uses_lrw() const noexcept { return use_lrw_; }

  // --- hot connect (SOEM ec_recover_slave; docs/master.md "Hot connect") ----------
  // A slave that no longer answers at its station address but does at its
  // position (a power cycle resets 0x0010 to 0): given a temporary station
  // address, its identity (SII words 8-13) compared with the scan's, then
  // its station address again. true: re-addressed; false: it still answers
  // at its address (nothing done). Errors: nothing at the position
  // (Timeout/WorkingCounter), another device there (WrongSlave: its
  // address is set back to 0).
  Expected<bool, MasterError> readdress(std::size_t slave);
  // The temporary station address readdress() uses (SOEM's EC_TEMPNODE).
  static constexpr std::uint16_t kTemporaryStation = 0xFFFF;

  // --- distributed clocks (masters.md §1.3 DC, §4.3; esc-registers.md §10) ---------
  // BWR 0x0900 latch, read port times and 0x0918 per DC slave, compute line
  // delays, write 0x0920 offsets and 0x0928 delays. Returns the DC slave count.
  Expected<std::size_t, MasterError> configure_dc(Nanoseconds master_time);
  // `iterations` x FRMW 0x0910:8 addressed at the reference clock (SOEM,
  // ethercrab), or ARMW by its position (TwinCAT, masters.md §3.3).
  Expected<void, MasterError> dc_static_drift_compensation(unsigned iterations, Command command = Command::Frmw);
  // 0x0981 = 0, 0x09A0 cycle, 0x0990 start (now + start_delay aligned to the cycle + shift), 0x0981 = 3;
  // then 0x0910 and 0x0990 read back: a start time that had passed when 0x0981 was written (the
  // master stalled longer than start_delay between its read of 0x0910 and that write, as on a
  // loaded host) leaves the unit waiting for the system time's wrap, and the slave would refuse Op
  // with 002Dh; it is programmed again from a fresh time, up to kSync0StartAttempts times in all
  // (Sync0StartMissed after the last). Returns the start time written last.
  Expected<std::uint64_t, MasterError> configure_sync0(std::size_t slave, std::uint32_t cycle_ns,
                                                       std::uint32_t shift_ns, Nanoseconds start_delay);
  static constexpr unsigned kSync0StartAttempts = 3;
  // After 0x0981 activated SYNC0: true when the unit runs or waits for a start time still ahead
  // (0x0990 read after 0x0910 lies after it), false when it missed its start and waits for the
  // wrap of the system time. Compared in 32 bits on an ESC without 64-bit DC (0x0008 bit 3).
  Expected<bool, MasterError> sync0_started(std::size_t slave);
  // Position of the first DC slave (reference clock), if any.
  std::optional<std::size_t> reference_clock() const noexcept { return reference_clock_; }

 private:
  // One programming of the SYNC unit (configure_sync0 checks it with sync0_started).
  Expected<std::uint64_t, MasterError> program_sync0(std::size_t slave, std::uint32_t cycle_ns, std::uint32_t shift_ns,
                                                     Nanoseconds start_delay);
  // Polls AL status until `wanted` or an error shows; with `ack` (the request
  // acknowledged an error) an error shown is the old one until the slave has
  // taken the request: polled on until it clears or the time is up.
  Expected<AlStatus, MasterError> poll_state(std::size_t slave, std::uint8_t wanted, bool ack);
  Expected<void, MasterError> sii_wait_idle(std::uint16_t station, std::uint16_t& status);
  Expected<std::size_t, MasterError> sii_read_word(std::uint16_t station, std::uint16_t word_address, Bytes out,
                                                   bool idle);
  Expected<void, MasterError> check_slave(std::size_t slave) const;
  Expected<void, MasterError> read_mailbox_area(std::size_t slave, bool& got);
  void set_mailbox_layout(std::size_t slave, const MailboxLayout& layout, bool enable);
  bool add_process_data_config(DatagramBatch& batch, const SlaveInfo& s);
  Expected<void, MasterError> write_station_address(std::uint16_t position, std::uint16_t station);

  transport::Transport& transport_;
  const Clock& clock_;
  MasterConfig config_;
  DatagramLink link_;
  std::vector<SlaveInfo> slaves_;
  mbx::MailboxErrorCode last_mailbox_error_ = mbx::MailboxErrorCode::None;
  std::vector<std::uint8_t> mailbox_buffer_;  // sized at configure_mailbox
  std::vector<std::uint8_t> image_;           // outputs, then inputs
  std::uint32_t output_bytes_ = 0;
  std::uint32_t input_bytes_ = 0;
  std::uint16_t expected_wkc_ = 0;
  bool pd_configured_ = false;                // configure_process_data() ran
  std::vector<PdDatagram> pd_plan_;           // the cyclic logical datagrams
  std::size_t pd_frames_ = 0;
  std::vector<Datagram> pd_datagrams_;        // [0] FRMW slot, then one per plan entry
  std::vector<std::size_t> pd_frame_begin_;   // frame f: pd_datagrams_[begin[f], begin[f+1])
  std::array<std::uint8_t, 2> al_status_{};  // cyclic BRD 0x0130 of a segment without process data
  CyclicStats cyclic_stats_{};
  std::optional<std::size_t> reference_clock_;
  bool dc_cyclic_ = false;
  bool use_lrw_ = true;
  std::array<std::uint8_t, 8> dc_time_{};
};

}  // namespace ecat::master
