// CoeClient::read_pdo_sizes for many slaves at once (issue 16 item 5): the
// same SDO uploads per slave in the same order (1C12h:00, 1C12h:i, each
// PDO's :00 and :j, then 1C13h), but every slave's next mailbox step (write
// the request into SM0, poll the SM1 status 0x080D, read SM1) goes into one
// round of datagrams packed into as few frames as fit, so N slaves wait for
// their replies together instead of one after the other. A slave whose
// conversation leaves the plain path (an abort other than "object does not
// exist" on 1C1xh:00, a mailbox error reply, a segmented answer, a value of
// the wrong size, a lost read, a timeout) is read again alone by
// CoeClient::read_pdo_sizes, which reports the error exactly as before.
#include <algorithm>
#include <array>
#include <optional>

#include "master/coe_client.hpp"
#include "master/datagram_batch.hpp"
#include "master/poll_budget.hpp"
#include "master/registers.hpp"

namespace ecat::master {

namespace {

using namespace coe;

enum class Io : std::uint8_t { Send, Poll, Read, Done, Alone };
enum class Ask : std::uint8_t { AssignCount, AssignEntry, MapCount, MapEntry };

constexpr std::uint32_t kEntryBitLengthMask = 0xFF;  // mapping entry: bits 7:0 = length
constexpr std::uint32_t kBitsPerByte = 8;
constexpr std::size_t kOutputsSm = 2;  // 1C12h's SM
constexpr std::size_t kInputsSm = 3;   // 1C13h's SM

// Process data on SM2 (outputs) and SM3 (inputs) only, so 1C12h/1C13h size
// it; any other process-data SM needs 1C10h+n (CoeClient's per-SM path).
bool standard_process_sms(const SiiInfo& sii) {
  for (std::size_t n = 0; n < sii.sync_managers.size(); ++n) {
    const std::uint8_t t = sii.sync_managers[n].type;
    if (t == sii::kSmTypeOutputs && n != kOutputsSm) return false;
    if (t == sii::kSmTypeInputs && n != kInputsSm) return false;
  }
  return true;
}
constexpr std::size_t kSdoIndexAt = 3;           // index (u16) and subindex bytes of the SDO header
constexpr std::size_t kSdoSubindexAt = 5;
constexpr std::size_t kUploadData = 6;           // expedited data / normal size field
constexpr std::uint8_t kExpeditedSizeShift = 2;  // bits 3:2 = 4 - size
// Mailbox header + CoE header + SDO header + 4 data bytes: an expedited
// upload answer, an abort, an emergency, or a normal upload of up to 4 bytes.
constexpr std::size_t kShortReply = mbx::kHeaderSize + kCoeHeaderSize + kSdoHeaderSize + 4;

std::uint16_t mailbox_last_byte(std::uint16_t start, std::uint16_t size) noexcept {
  return static_cast<std::uint16_t>(start + size - 1);
}

struct PdoReader {
  std::size_t slave = 0;
  Io io = Io::Send;
  unsigned dir = 0;  // 0: 1C12h (outputs), 1: 1C13h (inputs)
  Ask ask = Ask::AssignCount;
  std::uint8_t count = 0;  // entries of the assignment / of the current PDO
  std::uint8_t at = 0;     // subindex being read
  std::vector<std::uint16_t> pdos;
  std::size_t pdo = 0;
  std::uint32_t bits[2]{};
  std::uint8_t counter = 0;
  std::optional<PollBudget> budget;

  std::uint16_t assign() const noexcept { return dir == 0 ? kRxPdoAssign : kTxPdoAssign; }
  std::uint16_t index() const noexcept { return ask == Ask::AssignCount || ask == Ask::AssignEntry ? assign() : pdos[pdo]; }
  std::uint8_t subindex() const noexcept { return ask == Ask::AssignCount || ask == Ask::MapCount ? 0 : at; }

  void next_dir() noexcept {
    ++dir;
    ask = Ask::AssignCount;
    io = dir == 2 ? Io::Done : Io::Send;
  }
  void next_pdo() noexcept {
    if (pdo < pdos.size()) ++pdo;
    if (pdo >= pdos.size()) return next_dir();
    ask = Ask::MapCount;
    io = Io::Send;
  }
  // The value of the current upload; false: leave the plain path.
  bool take(ConstBytes v) {
    io = Io::Send;
    switch (ask) {
      case Ask::AssignCount:
        if (v.size() != 1) return false;
        count = v[0];
        pdos.clear();
        pdo = 0;
        at = 1;
        ask = Ask::AssignEntry;
        if (count == 0) next_pdo();
        return true;
      case Ask::AssignEntry:
        if (v.size() != 2) return false;
        pdos.push_back(load_le<std::uint16_t>(v.data()));
        if (at++ == count) {
          pdo = 0;
          ask = Ask::MapCount;
          if (pdos.empty()) next_dir();
        }
        return true;
      case Ask::MapCount:
        if (v.size() != 1) return false;
        count = v[0];
        at = 1;
        ask = Ask::MapEntry;
        if (count == 0) next_pdo();
        return true;
      case Ask::MapEntry:
        if (v.size() != 4) return false;
        bits[dir] += load_le<std::uint32_t>(v.data()) & kEntryBitLengthMask;
        if (at++ == count) next_pdo();
        return true;
    }
    return false;
  }
};

enum class Reply : std::uint8_t { Value, Emergency, NotFound, Other };

// An SDO upload-initiate answer to (index, subindex) as CoeClient::upload
// takes it, without segments: the value bytes into `value`.
Reply parse_reply(ConstBytes p, std::uint16_t index, std::uint8_t subindex, ConstBytes& value) {
  if (p.size() < kCoeHeaderSize) return Reply::Other;
  const auto service = static_cast<std::uint8_t>(load_le<std::uint16_t>(p.data()) >> kServiceShift);
  if (service == kServiceEmergency) return Reply::Emergency;
  if (p.size() < kCoeHeaderSize + kSdoHeaderSize) return Reply::Other;
  const std::uint8_t cmd = p[kCoeHeaderSize];
  if (cmd == kAbort) {
    const auto code = static_cast<SdoAbortCode>(load_le<std::uint32_t>(p.data() + kUploadData));
    return code == SdoAbortCode::ObjectNotFound ? Reply::NotFound : Reply::Other;
  }
  if (service != kServiceSdoResponse || load_le<std::uint16_t>(p.data() + kSdoIndexAt) != index || p[kSdoSubindexAt] != subindex ||
      (cmd >> kSpecifierShift) != kScsUploadInitiate) {
    return Reply::Other;
  }
  if ((cmd & kExpedited) != 0) {
    const std::size_t size = (cmd & kSizeIndicated) != 0 ? 4 - ((cmd >> kExpeditedSizeShift) & 0x03) : 4;
    value = p.subspan(kUploadData, size);
    return Reply::Value;
  }
  const std::uint32_t complete = load_le<std::uint32_t>(p.data() + kUploadData);
  const ConstBytes data = p.subspan(kCoeHeaderSize + kSdoHeaderSize);
  if (data.size() < complete) return Reply::Other;  // segmented: CoeClient's path
  value = data.first(complete);
  return Reply::Value;
}

}  // namespace

Expected<void, SdoError> read_pdo_sizes_all(Master& master, std::span<const std::size_t> slaves) {
  const MasterConfig& cfg = master.config();
  std::vector<PdoReader> readers;
  for (std::size_t i : slaves) {
    if (i >= master.slave_count()) return fail(SdoError::master(MasterError::InvalidArgument));
    PdoReader r;
    r.slave = i;
    if (!master.slave(i).mailbox.configured || !standard_process_sms(master.slave(i).sii)) r.io = Io::Alone;
    readers.push_back(std::move(r));
  }
  DatagramBatch batch;
  std::vector<std::size_t> active;
  std::vector<std::size_t> first;  // the active slave's first datagram in the batch
  for (;;) {
    batch.clear();
    active.clear();
    first.clear();
    std::size_t at = 0;
    for (std::size_t k = 0; k < readers.size(); ++k) {
      PdoReader& r = readers[k];
      if (r.io == Io::Done || r.io == Io::Alone) continue;
      const SlaveInfo& s = master.slave(r.slave);
      if (!r.budget) {
        r.budget.emplace(master.clock(), cfg.mailbox_timeout, cfg.max_polls);
        if (r.io == Io::Send) r.counter = mbx::next_counter(s.mailbox_counter);
      }
      if (r.io != Io::Read && !r.budget->next()) {
        r.io = Io::Alone;
        continue;
      }
      switch (r.io) {
        case Io::Send: {
          // Header + request, then the last byte of SM0 in the same frame: the
          // buffer is full once its last byte is written (ESC Section I,
          // mailbox SM; TwinCAT writes SM0 so, masters.md §3.4), 41 bytes on the
          // wire per slave instead of the whole area.
          const auto req = CoeClient::upload_request(r.index(), r.subindex(), false);
          std::array<std::uint8_t, mbx::kHeaderSize + kCoeHeaderSize + kSdoHeaderSize> msg{};
          if (s.mailbox.rx_size < msg.size()) {
            r.io = Io::Alone;  // does not fit: CoeClient reports it
            continue;
          }
          ByteWriter w(msg);
          w.u16(static_cast<std::uint16_t>(req.size()));
          w.u16(0);
          w.u8(0);
          w.u8(static_cast<std::uint8_t>(mbx::kTypeCoe | (r.counter << mbx::kCounterShift)));
          w.bytes(req);
          batch.add(Command::Fpwr, device_address(s.station_address, s.mailbox.rx_start), msg);
          if (s.mailbox.rx_size > msg.size()) {
            const std::uint8_t last[1]{0};
            batch.add(Command::Fpwr,
                      device_address(s.station_address, mailbox_last_byte(s.mailbox.rx_start, s.mailbox.rx_size)),
                      last);
          }
          break;
        }
        case Io::Poll:
          batch.add_zeros(Command::Fprd,
                          device_address(s.station_address,
                                         static_cast<std::uint16_t>(reg::sync_manager(1) + reg::kSmStatusOffset)),
                          1);
          break;
        case Io::Read:
          // The header and an upload answer of up to 4 data bytes, then the
          // last byte, which frees SM1 (TwinCAT reads SM1 so). A longer reply
          // is cut: that slave is read again alone (a fresh request).
          if (s.mailbox.tx_size <= kShortReply) {
            batch.add_zeros(Command::Fprd, device_address(s.station_address, s.mailbox.tx_start), s.mailbox.tx_size);
          } else {
            batch.add_zeros(Command::Fprd, device_address(s.station_address, s.mailbox.tx_start), kShortReply);
            batch.add_zeros(Command::Fprd,
                            device_address(s.station_address, mailbox_last_byte(s.mailbox.tx_start, s.mailbox.tx_size)), 1);
          }
          break;
        case Io::Done:
        case Io::Alone: break;
      }
      active.push_back(k);
      first.push_back(at);
      at = batch.size();
    }
    if (active.empty()) break;
    if (auto x = batch.exchange(master.link()); !x) return fail(SdoError::master(x.error()));
    for (std::size_t a = 0; a < active.size(); ++a) {
      PdoReader& r = readers[active[a]];
      const std::size_t n = first[a];
      const std::size_t parts = (a + 1 < active.size() ? first[a + 1] : batch.size()) - n;
      SlaveInfo& s = master.slave(r.slave);
      const ConstBytes data = batch.data(n);
      switch (r.io) {
        case Io::Send:
          if (batch.wkc(n) != 1) break;  // SM0 still full: again while the budget lasts
          if (parts == 2 && batch.wkc(n + 1) != 1) {
            r.io = Io::Alone;  // the first part went in, the last byte did not
            break;
          }
          s.mailbox_counter = r.counter;
          r.io = Io::Poll;
          r.budget.reset();
          break;
        case Io::Poll:
          if (batch.wkc(n) != 1) {
            r.io = Io::Alone;
          } else if ((data[0] & reg::kSmStatusMailboxFull) != 0) {
            r.io = Io::Read;
          }
          break;
        case Io::Read: {
          r.budget.reset();
          if (batch.wkc(n) != 1 || (parts == 2 && batch.wkc(n + 1) != 1)) {  // full but not read: the repeat request is CoeClient's
            r.io = Io::Alone;
            break;
          }
          ByteReader rd(data);
          const std::uint16_t length = rd.u16();
          rd.skip(3);
          const std::uint8_t type = rd.u8() & mbx::kTypeMask;
          if (type != mbx::kTypeCoe || length > rd.remaining()) {
            r.io = Io::Alone;
            break;
          }
          ConstBytes value;
          switch (parse_reply(rd.bytes(length), r.index(), r.subindex(), value)) {
            case Reply::Emergency: r.io = Io::Poll; break;  // kept waiting, as CoeClient does
            case Reply::NotFound:
              if (r.ask == Ask::AssignCount) {
                r.bits[r.dir] = 0;  // ETG.1000.6 §5.6.7.4.2: no SM of that direction
                r.next_dir();
              } else {
                r.io = Io::Alone;
              }
              break;
            case Reply::Value:
              if (!r.take(value)) r.io = Io::Alone;
              break;
            case Reply::Other: r.io = Io::Alone; break;
          }
          break;
        }
        case Io::Done:
        case Io::Alone: break;
      }
    }
  }
  for (const PdoReader& r : readers) {
    if (r.io == Io::Alone) {
      CoeClient coe(master, r.slave);
      if (auto x = coe.read_pdo_sizes(); !x) return fail(x.error());
      continue;
    }
    auto& pd = master.slave(r.slave).pd;
    pd.per_sm = false;
    pd.output_bytes = static_cast<std::uint16_t>((r.bits[0] + kBitsPerByte - 1) / kBitsPerByte);
    pd.input_bytes = static_cast<std::uint16_t>((r.bits[1] + kBitsPerByte - 1) / kBitsPerByte);
  }
  return {};
}

}  // namespace ecat::master
