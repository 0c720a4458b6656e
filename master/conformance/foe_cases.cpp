// File access over EtherCAT (ETG.1000.6 §5.3.2 FoE; shared/spec/coe-mailbox.md
// §10: 6-byte header opcode/reserved/UINT32, RRQ/WRQ/DATA/ACK/ERR/BUSY,
// error codes 0x800x): a file written in packets and read back, the packet
// numbers both ways, and the error answers. Skipped, with the SII's answer,
// on a device that does not list FoE; the write cases skip with the error a
// device gives when it refuses to store a file.
#include <algorithm>

#include "master/conformance/suite.hpp"

namespace ecat::master::conformance {

namespace {

constexpr std::uint8_t kRrq = 1;
constexpr std::uint8_t kWrq = 2;
constexpr std::uint8_t kData = 3;
constexpr std::uint8_t kAck = 4;
constexpr std::uint8_t kErr = 5;
constexpr std::uint8_t kBusy = 6;
constexpr std::size_t kHeader = 6;
constexpr std::size_t kMailboxHeader = 6;
constexpr std::uint32_t kNotFound = 0x8001;
constexpr std::uint32_t kAccessDenied = 0x8002;
constexpr std::uint32_t kDiskFull = 0x8003;
constexpr std::uint32_t kPacketNumber = 0x8005;
constexpr std::uint32_t kNoRights = 0x800A;
constexpr unsigned kBusyRetries = 100;
// BUSY: the UINT32 field is Done (UINT16) then Entire (UINT16) (coe-mailbox.md §10).
constexpr unsigned kBusyEntireShift = 16;
constexpr char kFileName[] = "ecat-conform.bin";
constexpr char kAbsentName[] = "ecat-conform-absent.bin";

struct Reply {
  std::uint8_t opcode = 0;
  std::uint8_t reserved = 0;
  std::uint32_t value = 0;  // password / packet / error code
  std::vector<std::uint8_t> data;
};

std::string describe(const Reply& r) {
  switch (r.opcode) {
    case kData: return "DATA(" + std::to_string(r.value) + ")";
    case kAck: return "ACK(" + std::to_string(r.value) + ")";
    case kErr: return "ERR " + hex(r.value, 4);
    case kBusy:
      return "BUSY(" + std::to_string(r.value & 0xFFFF) + "/" + std::to_string(r.value >> kBusyEntireShift) + ")";
    default: return "opcode " + std::to_string(r.opcode);
  }
}

std::vector<std::uint8_t> request(std::uint8_t opcode, std::uint32_t value, ConstBytes data) {
  std::vector<std::uint8_t> out(kHeader + data.size(), 0);
  out[0] = opcode;
  store_le<std::uint32_t>(out.data() + 2, value);
  std::copy(data.begin(), data.end(), out.begin() + kHeader);
  return out;
}

Expected<Reply, std::string> foe_exchange(Context& ctx, const std::vector<std::uint8_t>& req) {
  Master& m = ctx.master();
  if (auto s = m.mailbox_send(ctx.slave(), mbx::kTypeFoe, req); !s) return fail("send: " + std::string(ecat::master::describe(s.error())));
  for (;;) {
    auto msg = m.mailbox_receive(ctx.slave(), m.config().mailbox_timeout);
    if (!msg) {
      if (msg.error() == MasterError::MailboxErrorReply) {
        return fail("mailbox error " + hex(static_cast<std::uint16_t>(m.last_mailbox_error()), 4));
      }
      return fail(std::string(ecat::master::describe(msg.error())));
    }
    if (msg->header.type != mbx::kTypeFoe) continue;  // an emergency in between
    if (msg->payload.size() < kHeader) return fail("FoE reply of " + std::to_string(msg->payload.size()) + " bytes");
    Reply r;
    r.opcode = msg->payload[0];
    r.reserved = msg->payload[1];
    r.value = load_le<std::uint32_t>(msg->payload.data() + 2);
    r.data.assign(msg->payload.begin() + kHeader, msg->payload.end());
    return r;
  }
}

std::vector<std::uint8_t> name_bytes(const char* name) {
  return std::vector<std::uint8_t>(name, name + std::char_traits<char>::length(name));
}

std::optional<CaseResult> need_foe(Context& ctx) {
  if (auto r = ctx.go_to(AlState::PreOp); !r) return CaseResult::failed("reach PreOp", r.error());
  if ((ctx.info().sii.mailbox_protocols & sii::kProtoFoe) == 0) return CaseResult::skip("no FoE in the SII mailbox protocols");
  return std::nullopt;
}

std::uint32_t password(const Context& ctx) { return ctx.options().foe_password.value_or(0); }

std::size_t write_room(Context& ctx) { return ctx.info().sii.rx_mailbox_size - kMailboxHeader - kHeader; }

// An RRQ/WRQ sent again while the device answers BUSY (ETG.1000.6 §5.3.2:
// the master repeats the request); the first other reply. The BUSY replies
// go to `busy` when given.
Expected<Reply, std::string> open_request(Context& ctx, std::uint8_t opcode, std::uint32_t pw, const char* name,
                                          std::vector<Reply>* busy = nullptr) {
  for (unsigned i = 0; i < kBusyRetries; ++i) {
    auto r = foe_exchange(ctx, request(opcode, pw, name_bytes(name)));
    if (!r || r->opcode != kBusy) return r;
    if (busy) busy->push_back(*r);
    ctx.wait(std::chrono::milliseconds(1));
  }
  return fail("BUSY " + std::to_string(kBusyRetries) + " times");
}

// WRQ and its ACK(0), retrying on BUSY; a skip when the device refuses.
std::optional<CaseResult> open_write(Context& ctx, const char* name, std::vector<Reply>* busy = nullptr) {
  auto r = open_request(ctx, kWrq, password(ctx), name, busy);
  if (!r) return CaseResult::failed("ACK(0) to WRQ", r.error());
  if (r->opcode == kErr) return CaseResult::skip("the device refuses to store a file: " + describe(*r));
  if (r->opcode != kAck || r->value != 0) return CaseResult::failed("ACK(0) to WRQ", describe(*r));
  return std::nullopt;
}

// A file of 2.5 write packets: the last packet short ends it.
std::vector<std::uint8_t> test_file(Context& ctx) {
  std::vector<std::uint8_t> f(write_room(ctx) * 5 / 2);
  for (std::size_t i = 0; i < f.size(); ++i) f[i] = static_cast<std::uint8_t>(i * 7 + 3);
  return f;
}

// Writes the file; the ACK packet numbers seen, or a case result.
Expected<std::string, CaseResult> write_file(Context& ctx, const std::vector<std::uint8_t>& file,
                                             std::vector<Reply>* busy = nullptr) {
  if (auto c = open_write(ctx, kFileName, busy)) return fail(*c);
  const std::size_t room = write_room(ctx);
  std::string acks;
  std::uint32_t packet = 1;
  for (std::size_t at = 0;; ++packet) {
    const std::size_t n = std::min(room, file.size() - at);
    auto r = foe_exchange(ctx, request(kData, packet, ConstBytes(file.data() + at, n)));
    if (!r) return fail(CaseResult::failed("ACK(" + std::to_string(packet) + ")", r.error()));
    acks += (acks.empty() ? "" : " ") + describe(*r);
    at += n;
    if (n < room) break;
  }
  return acks;
}

// Reads the file; the DATA packet numbers and the bytes.
Expected<std::pair<std::string, std::vector<std::uint8_t>>, std::string> read_file(Context& ctx, const char* name,
                                                                                   std::vector<Reply>* busy = nullptr) {
  std::string packets;
  std::vector<std::uint8_t> bytes;
  auto r = open_request(ctx, kRrq, password(ctx), name, busy);
  const std::size_t room = ctx.info().sii.tx_mailbox_size - kMailboxHeader - kHeader;
  for (unsigned guard = 0; guard < 1000; ++guard) {
    if (!r) return fail(r.error());
    if (r->opcode != kData) return fail(describe(*r));
    packets += (packets.empty() ? "" : " ") + describe(*r);
    bytes.insert(bytes.end(), r->data.begin(), r->data.end());
    const bool last = r->data.size() < room;
    const std::uint32_t number = r->value;
    if (last) {
      // The final ACK has no reply to wait for.
      (void)ctx.master().mailbox_send(ctx.slave(), mbx::kTypeFoe, request(kAck, number, {}));
      return std::make_pair(packets, bytes);
    }
    r = foe_exchange(ctx, request(kAck, number, {}));
  }
  return fail(std::string("no end of file"));
}

std::string numbered(const char* op, unsigned n) {
  std::string s;
  for (unsigned k = 1; k <= n; ++k) s += (k > 1 ? " " : "") + std::string(op) + "(" + std::to_string(k) + ")";
  return s;
}

unsigned packets_for(std::size_t bytes, std::size_t room) { return static_cast<unsigned>(bytes / room + 1); }

}  // namespace

std::vector<Case> foe_cases() {
  std::vector<Case> cases;
  cases.push_back({"foe.write_ack_numbers", "ETG.1000.6 §5.3.2 FoE write (shared/spec/coe-mailbox.md §10): WRQ -> ACK(0), each DATA(k) -> ACK(k), a short DATA ends the file",
                   [](Context& ctx) {
                     if (auto c = need_foe(ctx)) return *c;
                     const auto file = test_file(ctx);
                     auto acks = write_file(ctx, file);
                     if (!acks) return acks.error();
                     return CaseResult::compare(numbered("ACK", packets_for(file.size(), write_room(ctx))), *acks);
                   }});
  cases.push_back({"foe.read_back", "ETG.1000.6 §5.3.2 FoE read (shared/spec/coe-mailbox.md §10): RRQ of a file just written returns its bytes",
                   [](Context& ctx) {
                     if (auto c = need_foe(ctx)) return *c;
                     const auto file = test_file(ctx);
                     if (auto acks = write_file(ctx, file); !acks) return acks.error();
                     auto r = read_file(ctx, kFileName);
                     if (!r) return CaseResult::failed(std::to_string(file.size()) + " bytes, same", r.error());
                     return CaseResult::compare(std::to_string(file.size()) + " bytes, same",
                                                std::to_string(r->second.size()) + " bytes, " + (r->second == file ? "same" : "different"));
                   }});
  cases.push_back({"foe.read_packet_numbers", "ETG.1000.6 §5.3.2 FoE read (shared/spec/coe-mailbox.md §10): DATA packets numbered from 1, one up per ACK, the last one short",
                   [](Context& ctx) {
                     if (auto c = need_foe(ctx)) return *c;
                     const auto file = test_file(ctx);
                     if (auto acks = write_file(ctx, file); !acks) return acks.error();
                     auto r = read_file(ctx, kFileName);
                     if (!r) return CaseResult::failed("DATA packets", r.error());
                     const std::size_t room = ctx.info().sii.tx_mailbox_size - kMailboxHeader - kHeader;
                     return CaseResult::compare(numbered("DATA", packets_for(file.size(), room)), r->first);
                   }});
  cases.push_back({"foe.read_not_found", "ETG.1000.6 §5.3.2 FoE (shared/spec/coe-mailbox.md §10): RRQ of a file that does not exist -> ERR 0x8001 not found",
                   [](Context& ctx) {
                     if (auto c = need_foe(ctx)) return *c;
                     auto r = open_request(ctx, kRrq, password(ctx), kAbsentName);
                     // A device without a file store denies every access (a twin
                     // without --state-dir): it has no file to be found or not.
                     if (r && r->opcode == kErr && r->value == kAccessDenied) {
                       return CaseResult::skip("the device has no file store: " + describe(*r));
                     }
                     return CaseResult::compare("ERR " + hex(kNotFound, 4), r ? describe(*r) : r.error());
                   }});
  cases.push_back({"foe.write_wrong_packet_number", "ETG.1000.6 §5.3.2 FoE (shared/spec/coe-mailbox.md §10): DATA(2) as the first packet of a write -> ERR 0x8005 packet number wrong",
                   [](Context& ctx) {
                     if (auto c = need_foe(ctx)) return *c;
                     if (auto c = open_write(ctx, kFileName)) return *c;
                     const std::uint8_t one[1]{0x55};
                     auto r = foe_exchange(ctx, request(kData, 2, one));
                     return CaseResult::compare("ERR " + hex(kPacketNumber, 4), r ? describe(*r) : r.error());
                   }});
  cases.push_back({"foe.access_denied", "ETG.1000.6 §5.3.2 FoE (shared/spec/coe-mailbox.md §10): RRQ of a file the device denies (ecat-conform --foe-denied NAME) -> ERR 0x8002 access denied",
                   [](Context& ctx) {
                     if (auto c = need_foe(ctx)) return *c;
                     const std::string& name = ctx.options().foe_denied_file;
                     if (name.empty()) return CaseResult::skip("which file a device denies is not in its ESI: give --foe-denied NAME");
                     auto r = open_request(ctx, kRrq, password(ctx), name.c_str());
                     return CaseResult::compare("ERR " + hex(kAccessDenied, 4), r ? describe(*r) : r.error());
                   }});
  cases.push_back({"foe.wrong_password", "ETG.1000.6 §5.3.2 FoE RRQ/WRQ password (shared/spec/coe-mailbox.md §10): WRQ with another password than the device's (--foe-password) -> ERR 0x800A no rights (SOES) or 0x8002 access denied, nothing written",
                   [](Context& ctx) {
                     if (auto c = need_foe(ctx)) return *c;
                     if (!ctx.options().foe_password) return CaseResult::skip("whether a device's files need a password is not in its ESI: give --foe-password N");
                     const std::uint32_t wrong = *ctx.options().foe_password + 1;
                     auto r = open_request(ctx, kWrq, wrong, kFileName);
                     const std::string want = "ERR " + hex(kNoRights, 4) + " (or " + hex(kAccessDenied, 4) + ")";
                     if (!r) return CaseResult::failed(want, r.error());
                     if (r->opcode == kAck) {
                       // Taken: end the write the way a master gives up.
                       (void)ctx.master().mailbox_send(ctx.slave(), mbx::kTypeFoe, request(kErr, kNoRights, {}));
                     }
                     const bool ok = r->opcode == kErr && (r->value == kNoRights || r->value == kAccessDenied);
                     return ok ? CaseResult::pass(want, describe(*r)) : CaseResult::failed(want, describe(*r));
                   }});
  cases.push_back({"foe.write_disk_full", "ETG.1000.6 §5.3.2 FoE write (shared/spec/coe-mailbox.md §10): a file longer than the device can store (--foe-capacity BYTES) ends with ERR 0x8003 disk full, not a last ACK",
                   [](Context& ctx) {
                     if (auto c = need_foe(ctx)) return *c;
                     if (!ctx.options().foe_capacity) return CaseResult::skip("a device's FoE storage is not in its ESI: give --foe-capacity BYTES");
                     const std::size_t room = write_room(ctx);
                     const std::size_t size = (*ctx.options().foe_capacity / room + 2) * room + room / 2;
                     if (auto c = open_write(ctx, kFileName)) return *c;
                     std::vector<std::uint8_t> packet(room, 0xA5);
                     const std::string want = "ERR " + hex(kDiskFull, 4);
                     std::uint32_t number = 1;
                     for (std::size_t at = 0; at < size; ++number) {
                       const std::size_t n = std::min(room, size - at);
                       auto r = foe_exchange(ctx, request(kData, number, ConstBytes(packet.data(), n)));
                       if (!r) return CaseResult::failed(want, r.error());
                       if (r->opcode == kErr) return CaseResult::compare(want, describe(*r));
                       if (r->opcode != kAck || r->value != number) return CaseResult::failed(want, "DATA(" + std::to_string(number) + ") -> " + describe(*r));
                       at += n;
                     }
                     return CaseResult::failed(want, "all " + std::to_string(size) + " bytes taken (ACK(" + std::to_string(number - 1) + "))");
                   }});
  cases.push_back({"foe.busy_then_complete", "ETG.1000.6 §5.3.2 FoE Busy (opcode 6; shared/spec/coe-mailbox.md §10): a device that is busy (--foe-busy) answers BUSY with reserved 0 and Done (UINT16) <= Entire (UINT16), and serves the request when the master sends it again: the file written and read back whole",
                   [](Context& ctx) {
                     if (auto c = need_foe(ctx)) return *c;
                     if (!ctx.options().foe_busy) return CaseResult::skip("whether a device answers BUSY is not in its ESI: give --foe-busy");
                     const auto file = test_file(ctx);
                     std::vector<Reply> busy;
                     if (auto acks = write_file(ctx, file, &busy); !acks) return acks.error();
                     auto r = read_file(ctx, kFileName, &busy);
                     const std::string whole = std::to_string(file.size()) + " bytes, same";
                     const std::string want = "BUSY (reserved 0, Done <= Entire), then " + whole;
                     if (!r) return CaseResult::failed(want, r.error());
                     std::string seen = busy.empty() ? "no BUSY" : "BUSY (reserved 0, Done <= Entire)";
                     for (const Reply& b : busy) {
                       if (b.reserved != 0 || (b.value & 0xFFFF) > (b.value >> kBusyEntireShift)) {
                         seen = describe(b) + " reserved " + hex(b.reserved, 2);
                         break;
                       }
                     }
                     seen += ", then " + std::to_string(r->second.size()) + " bytes, " + (r->second == file ? "same" : "different");
                     return CaseResult::compare(want, seen);
                   }});
  return cases;
}

}  // namespace ecat::master::conformance
