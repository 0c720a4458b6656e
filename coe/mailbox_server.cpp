#include "coe/mailbox_server.hpp"

#include <algorithm>
#include <cstring>

#include "coe/sm_bits.hpp"
#include "esc/registers.hpp"

namespace ecat::coe {
namespace {

constexpr std::size_t kReserveSlots = 1;  // kept free for a repeat that displaces SM1's content

bool mailbox_state(std::uint8_t s) noexcept {
  switch (static_cast<od::EsmState>(s)) {
    case od::EsmState::PreOp:
    case od::EsmState::SafeOp:
    case od::EsmState::Op:
    case od::EsmState::Bootstrap: return true;
    default: return false;
  }
}

}  // namespace

MailboxServer::MailboxServer(esc::Pdi& pdi, std::size_t max_mailbox_bytes, std::size_t queue_capacity)
    : pdi_(pdi),
      max_bytes_(max_mailbox_bytes),
      queue_(std::max<std::size_t>(queue_capacity, kReserveSlots + 1), max_mailbox_bytes),
      unsolicited_(std::max<std::size_t>(queue_capacity, 1),
                   std::min(max_mailbox_bytes, MailboxHeader::kSize + kMaxUnsolicitedPayload)),
      request_(max_mailbox_bytes),
      reply_(max_mailbox_bytes),
      sm1_image_(max_mailbox_bytes) {
  written_[0].resize(max_mailbox_bytes);
  written_[1].resize(max_mailbox_bytes);
}

bool MailboxServer::add_service(MailboxService& service) noexcept {
  if (service_count_ == services_.size()) return false;
  services_[service_count_++] = &service;
  if (service.starts_messages()) streamers_[streamer_count_++] = &service;
  note_idle();
  return true;
}

MailboxService* MailboxServer::replace_service(MailboxService& service) noexcept {
  for (std::size_t i = 0; i < service_count_; ++i) {
    if (services_[i]->type() != service.type()) continue;
    MailboxService* old = services_[i];
    services_[i] = &service;
    for (std::size_t k = 0; k < streamer_count_; ++k) {
      if (streamers_[k] == old) streamers_[k] = &service;
    }
    return old;
  }
  return nullptr;
}

MailboxService* MailboxServer::find(std::uint8_t type) const noexcept {
  for (std::size_t i = 0; i < service_count_; ++i) {
    if (static_cast<std::uint8_t>(services_[i]->type()) == type) return services_[i];
  }
  return nullptr;
}

MailboxServer::SmRegs MailboxServer::read_sm(unsigned n) noexcept {
  std::uint8_t raw[esc::reg::kSyncManagerStride]{};
  pdi_.read(esc::reg::sync_manager(n), raw);
  SmRegs sm;
  sm.start = load_le<std::uint16_t>(raw + esc::reg::sm::kStartAddress);
  sm.length = load_le<std::uint16_t>(raw + esc::reg::sm::kLength);
  sm.status = raw[esc::reg::sm::kStatus];
  sm.activate = raw[esc::reg::sm::kActivate];
  sm.pdi_control = raw[esc::reg::sm::kPdiControl];
  return sm;
}

bool MailboxServer::usable(const SmRegs& sm) const noexcept {
  return (sm.activate & bits::kSmActivateEnable) && !(sm.pdi_control & bits::kSmPdiDeactivate) &&
         sm.length > MailboxHeader::kSize && sm.length <= max_bytes_;
}

void MailboxServer::close() noexcept {
  open_ = false;
  queue_.clear();
  unsolicited_.clear();
  continuing_ = nullptr;
  last_request_counter_ = 0;
  have_written_[0] = have_written_[1] = false;
  request_since_write_ = false;
  for (std::size_t i = 0; i < service_count_; ++i) services_[i]->reset();
}

void MailboxServer::poll(Nanoseconds now) noexcept {
  (void)now;
  poll_once();
  note_idle();
}

void MailboxServer::poll_once() noexcept {
  const std::uint8_t al = pdi_.read_u8(esc::reg::kAlStatus) & bits::kAlStateMask;
  if (!mailbox_state(al)) {
    state_ = od::EsmState::Init;
    if (open_) close();
    return;
  }
  state_ = static_cast<od::EsmState>(al);
  // The SM event bits of 0x0220 only say "look"; the SM status registers
  // read below are what decides, so a missed event costs nothing.
  (void)pdi_.read_u32(esc::reg::kAlEventRequest);
  const SmRegs sm0 = read_sm(kWriteMailboxSm);
  SmRegs sm1 = read_sm(kReadMailboxSm);
  if (!usable(sm0) || !usable(sm1)) {
    if (open_) close();
    return;
  }
  open_ = true;
  sm1_length_ = sm1.length;
  sm0_length_ = sm0.length;
  if ((sm1.activate ^ sm1.pdi_control) & bits::kSmActivateRepeatRequest) {
    handle_repeat_request(sm1);
    sm1 = read_sm(kReadMailboxSm);
  }
  if (storm_left_ > 0) refill_storm();
  const bool request_waiting = sm0.status & bits::kSmStatusMailboxFull;
  if (!held_ && deliver(sm1, !request_waiting)) sm1 = read_sm(kReadMailboxSm);
  if (request_waiting && queue_.size() + kReserveSlots < queue_.capacity()) {
    receive(sm0);
    if (!held_) deliver(sm1, false);
  }
}

// ESC datasheet Section I §8.2.3 (mailbox repeat): write the last reply
// again, then make the repeat ack equal the request.
void MailboxServer::handle_repeat_request(const SmRegs& sm1) noexcept {
  const int newest = newest_;
  const int older = 1 - newest_;
  if (repeat_ignored_) {
    // Test-only breakage: acknowledged below, nothing written again.
  } else if (sm1.status & bits::kSmStatusMailboxFull) {
    // SM1 is still full, so the master has not read what it holds. If a
    // request came after the frame before it was written, the master had
    // that one (a master repeats a lost reply before it asks anything new:
    // SOEM ecx_mbxreceive, TwinCAT) and the frame in SM1 is the one it
    // lost: its read never reached the ESC. Keep it (docs/coe.md "Mailbox
    // repeat"). Otherwise SM1 holds a newer frame written after the lost
    // one was read (a fragment, an emergency): empty SM1, send the lost one
    // and put the newer one back at the head (as SSC's mailbox.c does).
    if (have_written_[older] && !follows_request_[newest]) {
      pdi_.write_u8(static_cast<std::uint16_t>(esc::reg::sync_manager(kReadMailboxSm) + esc::reg::sm::kPdiControl),
                    static_cast<std::uint8_t>(sm1.pdi_control | bits::kSmPdiDeactivate));
      pdi_.write_u8(static_cast<std::uint16_t>(esc::reg::sync_manager(kReadMailboxSm) + esc::reg::sm::kPdiControl),
                    static_cast<std::uint8_t>(sm1.pdi_control & ~bits::kSmPdiDeactivate));
      (void)queue_.push_front({written_[newest].data(), written_length_[newest]});
      write_sm1(sm1, {written_[older].data(), written_length_[older]});
      newest_ = older;
    }
  } else if (have_written_[newest]) {
    write_sm1(sm1, {written_[newest].data(), written_length_[newest]});
  }
  const std::uint8_t ack = static_cast<std::uint8_t>((sm1.pdi_control & ~bits::kSmPdiRepeatAck) |
                                                     (sm1.activate & bits::kSmActivateRepeatRequest));
  pdi_.write_u8(static_cast<std::uint16_t>(esc::reg::sync_manager(kReadMailboxSm) + esc::reg::sm::kPdiControl),
                static_cast<std::uint8_t>(ack & ~bits::kSmPdiDeactivate));
}

void MailboxServer::write_sm1(const SmRegs& sm1, ConstBytes frame) noexcept {
  const std::size_t n = std::min<std::size_t>(frame.size(), sm1.length);
  if (n > 0) std::memmove(sm1_image_.data(), frame.data(), n);
  std::fill(sm1_image_.begin() + static_cast<std::ptrdiff_t>(n), sm1_image_.begin() + sm1.length, std::uint8_t{0});
  // Writing the last byte of the SM1 area makes the mailbox full for the master.
  pdi_.write(sm1.start, {sm1_image_.data(), sm1.length});
}

bool MailboxServer::busy() const noexcept {
  for (std::size_t i = 0; i < service_count_; ++i) {
    if (services_[i]->busy()) return true;
  }
  return false;
}

bool MailboxServer::deliver(const SmRegs& sm1, bool unsolicited_allowed) noexcept {
  if (sm1.status & bits::kSmStatusMailboxFull) return false;
  const int slot = 1 - newest_;
  std::size_t length = 0;
  auto next_reply = [&]() -> std::size_t {
    if (!queue_.empty()) {
      const ConstBytes frame = queue_.front();
      std::memcpy(written_[slot].data(), frame.data(), frame.size());
      queue_.pop_front();
      return frame.size();
    }
    return continuing_ ? next_fragment(slot, sm1.length) : 0;
  };
  // Messages a service starts itself (EoE frames) and replies take turns
  // when both wait, so neither starves the other (docs/eoe.md "Fairness").
  MailboxService* streamer = streamer_count_ == 0 ? nullptr : output_service();
  const bool replies_waiting = !queue_.empty() || continuing_ != nullptr;
  if (streamer && (!replies_waiting || reply_went_last_)) {
    length = next_output(slot, sm1.length, *streamer);
    if (length > 0) reply_went_last_ = false;
  }
  if (length == 0) {
    length = next_reply();
    if (length > 0) reply_went_last_ = true;
  }
  if (length == 0 && streamer) length = next_output(slot, sm1.length, *streamer);
  if (length == 0 && unsolicited_allowed && !unsolicited_.empty() && !busy()) {
    // Emergencies go out only while no request waits for its answer
    // (shared/spec/masters.md §6 #26: ethercrab fails on an emergency
    // in place of an SDO reply).
    const ConstBytes frame = unsolicited_.front();
    std::memcpy(written_[slot].data(), frame.data(), frame.size());
    length = frame.size();
    unsolicited_.pop_front();
  }
  if (length == 0) return false;
  written_length_[slot] = length;
  have_written_[slot] = true;
  follows_request_[slot] = request_since_write_;
  request_since_write_ = false;
  newest_ = slot;
  write_sm1(sm1, {written_[slot].data(), length});
  return true;
}

MailboxService* MailboxServer::output_service() const noexcept {
  for (std::size_t i = 0; i < streamer_count_; ++i) {
    if (streamers_[i]->has_output() && streamers_[i]->active_in(state_)) return streamers_[i];
  }
  return nullptr;
}

// A message the service starts itself: Address 0, priority 0, as an
// unsolicited message (docs/coe.md "Mailbox header of replies").
std::size_t MailboxServer::next_output(int slot, std::uint16_t sm1_length, MailboxService& service) noexcept {
  const std::size_t room = reply_limit_ == 0 ? static_cast<std::size_t>(sm1_length - MailboxHeader::kSize)
                                             : std::min<std::size_t>(sm1_length - MailboxHeader::kSize, reply_limit_);
  const std::size_t n = service.next_output({written_[slot].data() + MailboxHeader::kSize, room});
  if (n == 0) return 0;
  reply_header(service.type(), n, MailboxHeader{}).pack({written_[slot].data(), MailboxHeader::kSize});
  return MailboxHeader::kSize + n;
}

std::size_t MailboxServer::next_fragment(int slot, std::uint16_t sm1_length) noexcept {
  const std::size_t room = reply_limit_ == 0 ? static_cast<std::size_t>(sm1_length - MailboxHeader::kSize)
                                             : std::min<std::size_t>(sm1_length - MailboxHeader::kSize, reply_limit_);
  const std::size_t n = continuing_->next_reply({written_[slot].data() + MailboxHeader::kSize, room});
  if (n == 0) {
    continuing_ = nullptr;
    return 0;
  }
  reply_header(continuing_->type(), n, continuing_header_).pack({written_[slot].data(), MailboxHeader::kSize});
  return MailboxHeader::kSize + n;
}

// A reply goes back to whoever sent the request: the request's Address (0
// from a plain master; a gateway's tag otherwise, ETG.8200) and priority; the
// channel is always 0, the only one defined (ETG.1000.4 §5.6).
MailboxHeader MailboxServer::reply_header(MailboxType type, std::size_t payload_length,
                                          const MailboxHeader& to) noexcept {
  if (!counter_frozen_ || reply_counter_ == 0) reply_counter_ = MailboxHeader::next_counter(reply_counter_);
  MailboxHeader h;
  h.length = static_cast<std::uint16_t>(payload_length);
  h.address = to.address;
  h.priority = to.priority;
  h.type = static_cast<std::uint8_t>(type);
  h.counter = reply_counter_;
  return h;
}

void MailboxServer::receive(const SmRegs& sm0) noexcept {
  // Reading the whole area (last byte included) frees SM0 for the master.
  pdi_.read(sm0.start, {request_.data(), sm0.length});
  const auto header = MailboxHeader::unpack({request_.data(), sm0.length});
  if (!header) return;
  if (header->counter != 0 && header->counter == last_request_counter_ && !counter_ignored_) {
    // Same counter as the last request: a retry of a write whose WKC the
    // master did not see (ETG.1000.4 §5.6; SOES drops it too). The request
    // ran and its reply is on its way: drop the repeat. A second copy of the
    // reply could be taken for the answer to the master's next request.
    return;
  }
  last_request_counter_ = header->counter;
  request_since_write_ = true;
  request_header_ = *header;
  if (header->length > sm0.length - MailboxHeader::kSize) return queue_error(MailboxError::InvalidSize);
  if (header->length == 0 || header->type == static_cast<std::uint8_t>(MailboxType::Error)) {
    return queue_error(MailboxError::InvalidHeader);
  }
  if (header->channel != 0) return queue_error(MailboxError::InvalidChannel);
  if (error_reply_) {
    const MailboxError error = *error_reply_;
    if (error_replies_left_ > 0 && --error_replies_left_ == 0) error_reply_.reset();
    continuing_ = nullptr;
    return queue_error(error);
  }
  dispatch(*header, {request_.data() + MailboxHeader::kSize, header->length});
}

void MailboxServer::dispatch(const MailboxHeader& header, ConstBytes payload) noexcept {
  MailboxService* service = find(header.type);
  if (!service || !service->active_in(state_)) return queue_error(MailboxError::UnsupportedProtocol);
  continuing_ = nullptr;
  service->set_sizes(sm0_length_ - MailboxHeader::kSize, reply_room());
  const auto n = service->handle(payload, {reply_.data() + MailboxHeader::kSize, reply_room()}, state_);
  if (!n) return queue_error(n.error());
  if (*n > 0) queue_reply(service->type(), *n);
  continuing_ = service;
  continuing_header_ = header;
}

void MailboxServer::queue_reply(MailboxType type, std::size_t payload_length) noexcept {
  reply_header(type, payload_length, request_header_).pack({reply_.data(), MailboxHeader::kSize});
  const std::size_t length = MailboxHeader::kSize + payload_length;
  (void)queue_.push_back({reply_.data(), length});
}

void MailboxServer::queue_error(MailboxError error) noexcept {
  ByteWriter w({reply_.data() + MailboxHeader::kSize, kMailboxErrorPayload});
  w.u16(kMailboxErrorService);
  w.u16(static_cast<std::uint16_t>(error_code_override_.value_or(error)));
  queue_reply(MailboxType::Error, kMailboxErrorPayload);
}

Expected<void, MailboxError> MailboxServer::send(MailboxType type, ConstBytes payload) noexcept {
  if (!open_ || unsolicited_.full()) return fail(MailboxError::NoMoreMemory);
  if (payload.size() + MailboxHeader::kSize > sm1_length_ || payload.size() > kMaxUnsolicitedPayload) {
    return fail(MailboxError::InvalidSize);
  }
  std::uint8_t header[MailboxHeader::kSize];
  // The slave is the client of an unsolicited message: Address 0, the
  // master, and never a gateway's tag (docs/coe.md "Mailbox header of replies").
  reply_header(type, payload.size(), MailboxHeader{}).pack(header);
  // Build in SM1 image scratch: poll() is not running (single-threaded).
  std::memcpy(sm1_image_.data(), header, MailboxHeader::kSize);
  if (!payload.empty()) std::memcpy(sm1_image_.data() + MailboxHeader::kSize, payload.data(), payload.size());
  (void)unsolicited_.push_back({sm1_image_.data(), MailboxHeader::kSize + payload.size()});
  note_idle();
  return {};
}

bool MailboxServer::set_unsolicited_storm(MailboxType type, ConstBytes payload, std::uint64_t count) noexcept {
  if (payload.size() > storm_payload_.size()) return false;
  storm_type_ = type;
  std::copy(payload.begin(), payload.end(), storm_payload_.begin());
  storm_size_ = payload.size();
  storm_left_ = count;
  note_idle();
  return true;
}

// Keeps the unsolicited queue topped up from the storm: each copy goes
// through send() (its counter, its size checks) as any emergency does.
void MailboxServer::refill_storm() noexcept {
  while (storm_left_ > 0 && open_ && !unsolicited_.full()) {
    if (!send(storm_type_, {storm_payload_.data(), storm_size_})) {
      storm_left_ = 0;  // does not fit this SM1: nothing more to send
      return;
    }
    --storm_left_;
  }
}

}  // namespace ecat::coe
