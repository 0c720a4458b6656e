// A deliberately tiny ESC stand-in for exact-byte tests of the master: one
// slave, a flat 64 KiB memory, AL status mirroring AL control (device
// emulation), an SII interface that finishes at once with 8-byte reads, two
// FMMUs for LRW, and a mailbox pair at SM0/SM1 whose replies come from a
// test callback. Independent of esc/ so the master's wire bytes are tested
// on their own.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <vector>

#include "common/frame_parser.hpp"
#include "master/registers.hpp"

namespace ecat::master::test {

class FakeEsc {
 public:
  using MailboxHandler = std::function<std::vector<std::vector<std::uint8_t>>(std::vector<std::uint8_t> request)>;

  std::vector<std::uint8_t> mem = std::vector<std::uint8_t>(0x10000, 0);
  std::vector<std::uint8_t> sii;
  MailboxHandler on_mailbox;  // returns whole mailbox messages (header included) to queue in SM1
  std::deque<std::vector<std::uint8_t>> replies;
  std::uint16_t sm0 = 0x1000, sm1 = 0x1080, mbx_size = 128;
  bool lose_next_sm1_read = false;
  bool sii_read_8 = true;      // 0x0502 bit 6
  int sii_busy_reads = 0;      // reads of 0x0502 that still show busy after a command
  int busy_left_ = 0;

  std::uint16_t u16(std::uint16_t a) const { return load_le<std::uint16_t>(mem.data() + a); }

  void process(Bytes frame) {
    auto view = parse_frame(frame);
    if (!view) return;
    view->for_each([&](DatagramView d) { datagram(d); });
  }

 private:
  void datagram(DatagramView d) {
    bool hit = false;
    switch (addressing(d.command())) {
      case Addressing::AutoIncrement:
        hit = d.adp() == 0;
        d.set_adp(static_cast<std::uint16_t>(d.adp() + 1));
        break;
      case Addressing::Configured:
        hit = d.adp() == u16(reg::kConfiguredStationAddress);
        break;
      case Addressing::Broadcast:
        hit = true;
        d.set_adp(static_cast<std::uint16_t>(d.adp() + 1));
        break;
      case Addressing::Logical:
        logical(d);
        return;
      case Addressing::None:
        return;
    }
    if (!hit) return;
    const std::uint16_t ado = d.ado();
    Bytes data = d.data();
    if (d.command() == Command::Frmw) {
      // Reference clock: a read.
      read(ado, data, d);
      return;
    }
    if (reads(d.command())) read(ado, data, d);
    if (writes(d.command())) write(ado, data, d);
  }

  void read(std::uint16_t ado, Bytes data, DatagramView d) {
    const bool sm1_area = ado >= sm1 && ado < sm1 + mbx_size;
    if (sm1_area) {
      if ((mem[0x080D] & 0x08) == 0) return;  // empty: no WKC
      if (lose_next_sm1_read) {
        lose_next_sm1_read = false;
        return;  // as if the frame was lost on the way back: WKC 0
      }
    }
    if (ado == reg::kEepromControlStatus && busy_left_ > 0) {
      --busy_left_;
      store_le(mem.data() + reg::kEepromControlStatus, static_cast<std::uint16_t>(u16(reg::kEepromControlStatus) | 0x8000));
    } else if (ado == reg::kEepromControlStatus) {
      store_le(mem.data() + reg::kEepromControlStatus, static_cast<std::uint16_t>(u16(reg::kEepromControlStatus) & 0x7FFF));
    }
    for (std::size_t i = 0; i < data.size(); ++i) {
      const std::uint8_t v = mem[static_cast<std::uint16_t>(ado + i)];
      data[i] = d.command() == Command::Brd ? static_cast<std::uint8_t>(data[i] | v) : v;
    }
    d.add_wkc(1);
    if (sm1_area && ado + data.size() >= static_cast<std::size_t>(sm1 + mbx_size)) {
      last_reply_.assign(mem.begin() + sm1, mem.begin() + sm1 + mbx_size);
      mem[0x080D] = 0;
      next_reply();
    }
  }

  void write(std::uint16_t ado, Bytes data, DatagramView d) {
    const bool sm0_area = ado >= sm0 && ado < sm0 + mbx_size;
    if (sm0_area && (mem[0x0805] & 0x08) != 0) return;  // full
    for (std::size_t i = 0; i < data.size(); ++i) mem[static_cast<std::uint16_t>(ado + i)] = data[i];
    d.add_wkc(1);
    if (ado == reg::kAlControl) {
      mem[reg::kAlStatus] = static_cast<std::uint8_t>(data[0] & 0x0F);  // device emulation
    }
    if (ado == reg::kEepromControlStatus && data.size() >= 6 && (u16(reg::kEepromControlStatus) & 0x0700) == 0x0100) {
      const std::uint32_t word = load_le<std::uint32_t>(mem.data() + reg::kEepromAddress);
      const std::size_t n = sii_read_8 ? 8 : 4;
      for (std::size_t i = 0; i < 8; ++i) {
        const std::size_t at = 2 * word + i;
        mem[reg::kEepromData + i] = i < n && at < sii.size() ? sii[at] : 0xEE;
      }
      store_le(mem.data() + reg::kEepromControlStatus, static_cast<std::uint16_t>(sii_read_8 ? 0x0040 : 0x0000));
      busy_left_ = sii_busy_reads;
    }
    if (ado == 0x080E && data.size() == 1) {
      // Repeat request toggled: put the last reply back and acknowledge.
      mem[0x080F] = static_cast<std::uint8_t>((mem[0x080F] & ~0x02) | (data[0] & 0x02));
      std::copy(last_reply_.begin(), last_reply_.end(), mem.begin() + sm1);
      mem[0x080D] = 0x08;
    }
    if (sm0_area && ado + data.size() >= static_cast<std::size_t>(sm0 + mbx_size)) {
      std::vector<std::uint8_t> req(mem.begin() + sm0, mem.begin() + sm0 + mbx_size);
      if (on_mailbox) {
        for (auto& r : on_mailbox(req)) replies.push_back(std::move(r));
      }
      if ((mem[0x080D] & 0x08) == 0) next_reply();
    }
  }

  void next_reply() {
    if (replies.empty()) return;
    auto r = std::move(replies.front());
    replies.pop_front();
    std::fill(mem.begin() + sm1, mem.begin() + sm1 + mbx_size, 0);
    std::copy(r.begin(), r.end(), mem.begin() + sm1);
    mem[0x080D] = 0x08;
  }

  void logical(DatagramView d) {
    const std::uint32_t start = d.logical_address();
    Bytes data = d.data();
    bool wrote = false;
    bool read = false;
    for (unsigned f = 0; f < 4; ++f) {
      const std::uint16_t base = reg::fmmu(f);
      if (mem[base + 12] == 0) continue;
      const std::uint32_t lstart = load_le<std::uint32_t>(mem.data() + base);
      const std::uint16_t len = u16(static_cast<std::uint16_t>(base + 4));
      const std::uint16_t phys = u16(static_cast<std::uint16_t>(base + 8));
      const std::uint8_t type = mem[base + 11];
      if (lstart < start || lstart + len > start + data.size()) continue;
      const std::size_t off = lstart - start;
      if ((type & 0x02) != 0 && (d.command() == Command::Lrw || d.command() == Command::Lwr)) {
        for (std::size_t i = 0; i < len; ++i) mem[phys + i] = data[off + i];
        wrote = true;
      }
      if ((type & 0x01) != 0 && (d.command() == Command::Lrw || d.command() == Command::Lrd)) {
        for (std::size_t i = 0; i < len; ++i) data[off + i] = mem[phys + i];
        read = true;
      }
    }
    // Per ESC per datagram: +1 read, +2 write for LRW, +1 write for LWR (ETG.1000.4 §5.4.3).
    d.add_wkc(static_cast<std::uint16_t>((wrote ? (d.command() == Command::Lrw ? 2 : 1) : 0) + (read ? 1 : 0)));
  }

  std::vector<std::uint8_t> last_reply_;
};

}  // namespace ecat::master::test
