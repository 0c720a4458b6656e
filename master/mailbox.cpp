// Mailbox client (ETG.1000.4 §5.6, Section I §8.2; coe-mailbox.md §1-§3,
// masters.md §1.5): SM0/SM1 from the SII, whole-area writes into SM0 with the
// counter rotating 1..7, SM1 polled through its status bit 3, repeat request
// when a read of a full SM1 is lost.
#include <algorithm>
#include <array>
#include <cstring>

#include "master/datagram_batch.hpp"
#include "master/master.hpp"
#include "master/poll_budget.hpp"
#include "master/registers.hpp"

namespace ecat::master {

namespace {
constexpr std::uint8_t kDefaultRxControl = 0x26;  // mailbox, write, AL event
constexpr std::uint8_t kDefaultTxControl = 0x22;  // mailbox, read, AL event

std::array<std::uint8_t, 2 * reg::kSyncManagerSize> sm_pair_block(const MailboxLayout& layout, bool enable) {
  std::array<std::uint8_t, 2 * reg::kSyncManagerSize> sms{};
  ByteWriter w(sms);
  w.u16(layout.rx_start);
  w.u16(layout.rx_size);
  w.u8(layout.rx_control);
  w.u8(0);
  w.u8(enable ? reg::kSmActivateEnable : 0);
  w.u8(0);
  w.u16(layout.tx_start);
  w.u16(layout.tx_size);
  w.u8(layout.tx_control);
  w.u8(0);
  w.u8(enable ? reg::kSmActivateEnable : 0);
  w.u8(0);
  return sms;
}

// SM0/SM1 from the SII: lengths from words 0x19/0x1B (SOEM, ethercrab;
// masters.md §6 #18 asks both to agree), control bytes from the SYNCM
// category when present.
MailboxLayout sii_mailbox_layout(const SiiInfo& sii) {
  MailboxLayout l;
  l.rx_start = sii.rx_mailbox_offset;
  l.rx_size = sii.rx_mailbox_size;
  l.tx_start = sii.tx_mailbox_offset;
  l.tx_size = sii.tx_mailbox_size;
  l.rx_control = kDefaultRxControl;
  l.tx_control = kDefaultTxControl;
  if (sii.sync_managers.size() >= 2) {
    l.rx_control = sii.sync_managers[0].control;
    l.tx_control = sii.sync_managers[1].control;
  }
  return l;
}

}  // namespace

void Master::set_mailbox_layout(std::size_t slave, const MailboxLayout& layout, bool enable) {
  SlaveInfo& s = slaves_[slave];
  s.mailbox = layout;
  s.mailbox.configured = enable && layout.rx_size > 0 && layout.tx_size > 0;
  s.mailbox_counter = 0;
  const std::size_t need = std::max<std::size_t>(layout.rx_size, layout.tx_size);
  if (mailbox_buffer_.size() < need) mailbox_buffer_.resize(need);
}

Expected<void, MasterError> Master::write_mailbox_sms(std::size_t slave, const MailboxLayout& layout, bool enable) {
  if (auto c = check_slave(slave); !c) return fail(c.error());
  // Both off first (IgH clears them before configuring), then SM0 + SM1 in
  // one datagram (SOEM).
  const std::uint8_t off[2 * reg::kSyncManagerSize]{};
  if (auto r = fpwr(slaves_[slave].station_address, reg::sync_manager(0), off); !r) return fail(r.error());
  if (auto r = fpwr(slaves_[slave].station_address, reg::sync_manager(0), sm_pair_block(layout, enable)); !r) {
    return fail(r.error());
  }
  set_mailbox_layout(slave, layout, enable);
  return {};
}

Expected<void, MasterError> Master::configure_mailbox(std::size_t slave) {
  if (auto c = check_slave(slave); !c) return fail(c.error());
  const SiiInfo& sii = slaves_[slave].sii;
  if (!sii.has_mailbox()) return fail(MasterError::NoMailbox);
  return write_mailbox_sms(slave, sii_mailbox_layout(sii), true);
}

// The same two datagrams per slave as configure_mailbox, all slaves' in as
// few frames as fit (issue 16 item 5).
Expected<std::size_t, MasterError> Master::configure_mailboxes() {
  DatagramBatch batch;
  std::vector<std::size_t> with_mailbox;
  static constexpr std::array<std::uint8_t, 2 * reg::kSyncManagerSize> kOff{};
  for (std::size_t i = 0; i < slaves_.size(); ++i) {
    const SiiInfo& sii = slaves_[i].sii;
    if (!sii.has_mailbox()) continue;
    const auto at = device_address(slaves_[i].station_address, reg::sync_manager(0));
    batch.add(Command::Fpwr, at, kOff);
    batch.add(Command::Fpwr, at, sm_pair_block(sii_mailbox_layout(sii), true));
    with_mailbox.push_back(i);
  }
  if (batch.empty()) return std::size_t{0};
  if (auto r = batch.exchange(link_); !r) return fail(r.error());
  if (!batch.all_wkc(1)) return fail(MasterError::WorkingCounter);
  for (std::size_t i : with_mailbox) set_mailbox_layout(i, sii_mailbox_layout(slaves_[i].sii), true);
  return with_mailbox.size();
}

Expected<void, MasterError> Master::mailbox_send_raw(std::size_t slave, std::uint8_t type, std::uint8_t counter,
                                                     ConstBytes payload, std::uint16_t length_override) {
  if (auto c = check_slave(slave); !c) return fail(c.error());
  SlaveInfo& s = slaves_[slave];
  if (!s.mailbox.configured) return fail(MasterError::NotConfigured);
  const std::size_t size = s.mailbox.rx_size;
  if (payload.size() + mbx::kHeaderSize > size) return fail(MasterError::InvalidArgument);
  // Header + payload, rest of the area zero (rebuilt per attempt: the link
  // overwrites the buffer with the reply data).
  auto fill = [&] {
    std::fill(mailbox_buffer_.begin(), mailbox_buffer_.begin() + static_cast<std::ptrdiff_t>(size), 0);
    ByteWriter w(Bytes(mailbox_buffer_.data(), size));
    w.u16(length_override != 0xFFFF ? length_override : static_cast<std::uint16_t>(payload.size()));
    w.u16(0);  // address: master
    w.u8(0);   // channel 0, priority 0
    w.u8(static_cast<std::uint8_t>((type & mbx::kTypeMask) | ((counter & mbx::kCounterMask) << mbx::kCounterShift)));
    w.bytes(payload);
  };
  for (PollBudget budget(clock_, config_.mailbox_timeout, config_.max_polls); budget.next();) {
    fill();
    // The whole SM0 area in one datagram, so its last byte completes the buffer.
    auto wkc = link_.exchange(Command::Fpwr, device_address(s.station_address, s.mailbox.rx_start),
                              Bytes(mailbox_buffer_.data(), size));
    if (!wkc) return fail(wkc.error());
    if (*wkc == 1) return {};
    // WKC 0: mailbox still full (the slave has not read the last request).
  }
  return fail(MasterError::MailboxFull);
}

Expected<std::uint8_t, MasterError> Master::mailbox_send(std::size_t slave, std::uint8_t type, ConstBytes payload) {
  if (auto c = check_slave(slave); !c) return fail(c.error());
  const std::uint8_t counter = mbx::next_counter(slaves_[slave].mailbox_counter);
  if (auto r = mailbox_send_raw(slave, type, counter, payload); !r) return fail(r.error());
  slaves_[slave].mailbox_counter = counter;
  return counter;
}

Expected<bool, MasterError> Master::mailbox_has_reply(std::size_t slave) {
  if (auto c = check_slave(slave); !c) return fail(c.error());
  const SlaveInfo& s = slaves_[slave];
  auto status = fprd_u8(s.station_address, static_cast<std::uint16_t>(reg::sync_manager(1) + reg::kSmStatusOffset));
  if (!status) return fail(status.error());
  return (*status & reg::kSmStatusMailboxFull) != 0;
}

Expected<void, MasterError> Master::read_mailbox_area(std::size_t slave, bool& got) {
  const SlaveInfo& s = slaves_[slave];
  Bytes area(mailbox_buffer_.data(), s.mailbox.tx_size);
  std::fill(area.begin(), area.end(), 0);
  auto wkc = link_.exchange(Command::Fprd, device_address(s.station_address, s.mailbox.tx_start), area);
  if (!wkc) return fail(wkc.error());
  got = *wkc == 1;
  return {};
}

Expected<void, MasterError> Master::mailbox_repeat_request(std::size_t slave) {
  if (auto c = check_slave(slave); !c) return fail(c.error());
  const std::uint16_t station = slaves_[slave].station_address;
  const auto activate = static_cast<std::uint16_t>(reg::sync_manager(1) + reg::kSmActivateOffset);
  const auto pdi_control = static_cast<std::uint16_t>(reg::sync_manager(1) + reg::kSmPdiControlOffset);
  auto a = fprd_u8(station, activate);
  if (!a) return fail(a.error());
  const auto toggled = static_cast<std::uint8_t>(*a ^ reg::kSmActivateRepeat);
  if (auto r = fpwr_u8(station, activate, toggled); !r) return fail(r.error());
  for (PollBudget budget(clock_, config_.mailbox_timeout, config_.max_polls); budget.next();) {
    auto p = fprd_u8(station, pdi_control);
    if (!p) return fail(p.error());
    if ((*p & reg::kSmPdiRepeatAck) == (toggled & reg::kSmActivateRepeat)) return {};
  }
  return fail(MasterError::MailboxTimeout);
}

Expected<MailboxMessage, MasterError> Master::mailbox_receive(std::size_t slave, Nanoseconds timeout) {
  if (auto c = check_slave(slave); !c) return fail(c.error());
  const SlaveInfo& s = slaves_[slave];
  if (!s.mailbox.configured) return fail(MasterError::NotConfigured);
  bool repeated = false;
  for (PollBudget budget(clock_, timeout, config_.max_polls); budget.next();) {
    auto full = mailbox_has_reply(slave);
    if (!full) return fail(full.error());
    if (*full) {
      bool got = false;
      if (auto r = read_mailbox_area(slave, got); !r) return fail(r.error());
      if (!got) {
        // Full but the read did not count: ask for the reply again once.
        if (repeated) return fail(MasterError::MailboxTimeout);
        if (auto r = mailbox_repeat_request(slave); !r) return fail(r.error());
        repeated = true;
        continue;
      }
      ByteReader rd(ConstBytes(mailbox_buffer_.data(), s.mailbox.tx_size));
      MailboxMessage m;
      m.header.length = rd.u16();
      m.header.address = rd.u16();
      m.header.channel_priority = rd.u8();
      const std::uint8_t tc = rd.u8();
      m.header.type = tc & mbx::kTypeMask;
      m.header.counter = static_cast<std::uint8_t>((tc >> mbx::kCounterShift) & mbx::kCounterMask);
      if (m.header.length > rd.remaining()) return fail(MasterError::InvalidResponse);
      m.payload = rd.bytes(m.header.length);
      if (m.header.type == mbx::kTypeError) {
        ByteReader er(m.payload);
        (void)er.u16();  // service type 0x0001
        last_mailbox_error_ = static_cast<mbx::MailboxErrorCode>(er.u16());
        return fail(MasterError::MailboxErrorReply);
      }
      return m;
    }
  }
  return fail(MasterError::MailboxTimeout);
}

}  // namespace ecat::master
