// Ethernet over EtherCAT (ETG.1000.6 §5.7 EoE, mailbox type 2; the 4-byte
// header, frame types and results as docs/eoe.md lists them): Set/Get IP
// Parameter and Set Address Filter with their results, an unknown frame type,
// and Ethernet frames larger than the mailbox sent in fragments both ways.
// The frame is an ICMP echo request to the IP address the case gave the
// device; an EoE device whose Ethernet side has an IP stack answers it.
// Skipped, with the SII's answer, on a device that does not list EoE.
#include <algorithm>
#include <array>

#include "master/conformance/suite.hpp"

namespace ecat::master::conformance {

namespace {

constexpr std::size_t kMailboxHeader = 6;
constexpr std::size_t kEoeHeader = 4;
constexpr std::size_t kBlock = 32;  // unit of fragment offsets and frame sizes
constexpr std::uint8_t kFragmentData = 0;
constexpr std::uint8_t kSetIpRequest = 2;
constexpr std::uint8_t kSetIpResponse = 3;
constexpr std::uint8_t kSetFilterRequest = 4;
constexpr std::uint8_t kSetFilterResponse = 5;
constexpr std::uint8_t kGetIpRequest = 6;
constexpr std::uint8_t kGetIpResponse = 7;
constexpr std::uint8_t kUnknownType = 0x0A;  // not a frame type of ETG.1000.6
constexpr std::uint16_t kTypeMask = 0x000F;
constexpr std::uint16_t kLastFragment = 1u << 8;
constexpr std::uint16_t kTimeAppended = 1u << 9;
constexpr std::size_t kTimestamp = 4;
constexpr unsigned kOffsetShift = 6;
constexpr unsigned kFrameShift = 12;
constexpr std::uint16_t kSixBits = 0x003F;
constexpr std::uint16_t kSuccess = 0x0000;
constexpr std::uint16_t kUnsupportedFrameType = 0x0002;
constexpr std::uint16_t kNoFilterSupport = 0x0401;
constexpr std::uint16_t kServiceNotSupported = 0x0004;  // mailbox error (coe-mailbox.md §2)
// Set IP Parameter flags: MAC, IP, subnet, gateway, DNS server, DNS name.
// All are sent, so a slave that reads the fields packed (only flagged ones)
// and one that reads them at fixed places (TwinCAT, SOEM 2) agree.
constexpr std::uint32_t kAllIpFields = 0x3F;
constexpr std::uint32_t kHasIp = 1u << 1;
constexpr std::size_t kDnsName = 32;
constexpr std::size_t kMinFrame = 14;
constexpr std::size_t kMaxFrame = 1514;  // Ethernet without FCS

using Mac = std::array<std::uint8_t, 6>;
constexpr Mac kSlaveMac{0x02, 0x45, 0x43, 0x41, 0x54, 0x02};   // locally administered
constexpr Mac kMasterMac{0x02, 0x45, 0x43, 0x41, 0x54, 0xFE};
constexpr std::uint32_t kSlaveIp = 0xC0A84D02;   // 192.168.77.2
constexpr std::uint32_t kMasterIp = 0xC0A84D01;  // 192.168.77.1
constexpr std::uint32_t kSubnet = 0xFFFFFF00;
constexpr std::uint16_t kEtherIpv4 = 0x0800;
constexpr std::uint8_t kIcmp = 1;
constexpr std::uint8_t kEchoRequest = 8;
constexpr std::uint8_t kEchoReply = 0;
constexpr std::size_t kIpHeader = 20;
constexpr std::size_t kIcmpHeader = 8;
constexpr std::uint16_t kEchoId = 0xEC47;
constexpr unsigned kMaxMessages = 64;  // unsolicited messages looked at while waiting for one answer
constexpr Nanoseconds kNoAnswerWait = std::chrono::milliseconds(200);

std::optional<CaseResult> need_eoe(Context& ctx) {
  if (auto r = ctx.go_to(AlState::PreOp); !r) return CaseResult::failed("reach PreOp", r.error());
  if ((ctx.info().sii.mailbox_protocols & sii::kProtoEoe) == 0) return CaseResult::skip("no EoE in the SII mailbox protocols");
  return std::nullopt;
}

std::vector<std::uint8_t> eoe_request(std::uint8_t type, ConstBytes body) {
  std::vector<std::uint8_t> out(kEoeHeader + body.size(), 0);
  store_le<std::uint16_t>(out.data(), static_cast<std::uint16_t>(type | kLastFragment));
  std::copy(body.begin(), body.end(), out.begin() + kEoeHeader);
  return out;
}

struct Message {
  std::uint16_t word0 = 0;
  std::uint16_t word1 = 0;
  std::vector<std::uint8_t> body;
  std::uint8_t type() const { return static_cast<std::uint8_t>(word0 & kTypeMask); }
};

// The next EoE message from the slave (other mailbox types are skipped);
// "mailbox error 0x...." when the slave answers with one.
Expected<Message, std::string> receive_eoe(Context& ctx, Nanoseconds timeout) {
  Master& m = ctx.master();
  for (unsigned i = 0; i < kMaxMessages; ++i) {
    auto msg = m.mailbox_receive(ctx.slave(), timeout);
    if (!msg) {
      if (msg.error() == MasterError::MailboxErrorReply) {
        return fail("mailbox error " + hex(static_cast<std::uint16_t>(m.last_mailbox_error()), 4));
      }
      return fail(std::string(ecat::master::describe(msg.error())));
    }
    if (msg->header.type != mbx::kTypeEoe) continue;
    if (msg->payload.size() < kEoeHeader) return fail("EoE message of " + std::to_string(msg->payload.size()) + " bytes");
    Message r;
    r.word0 = load_le<std::uint16_t>(msg->payload.data());
    r.word1 = load_le<std::uint16_t>(msg->payload.data() + 2);
    r.body.assign(msg->payload.begin() + kEoeHeader, msg->payload.end());
    return r;
  }
  return fail(std::string("no EoE message among ") + std::to_string(kMaxMessages));
}

// Sends a request and waits for the response of `want` (fragments of
// Ethernet frames in between are skipped).
Expected<Message, std::string> eoe_exchange(Context& ctx, const std::vector<std::uint8_t>& req) {
  Master& m = ctx.master();
  if (auto s = m.mailbox_send(ctx.slave(), mbx::kTypeEoe, req); !s) return fail("send: " + std::string(ecat::master::describe(s.error())));
  for (unsigned i = 0; i < kMaxMessages; ++i) {
    auto r = receive_eoe(ctx, m.config().mailbox_timeout);
    if (!r) return r;
    if (r->type() != kFragmentData) return r;
  }
  return fail(std::string("no EoE response"));
}

std::string describe(const Message& r) { return "type " + std::to_string(r.type()) + ", result " + hex(r.word1, 4); }

void put_mac(std::vector<std::uint8_t>& out, const Mac& mac) { out.insert(out.end(), mac.begin(), mac.end()); }
void put_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  std::uint8_t b[4];
  store_le<std::uint32_t>(b, v);
  out.insert(out.end(), b, b + 4);
}

// Set IP Parameter with every field: MAC, IP, subnet, gateway 0, DNS 0, DNS name.
std::vector<std::uint8_t> set_ip_body() {
  std::vector<std::uint8_t> body;
  put_u32(body, kAllIpFields);
  put_mac(body, kSlaveMac);
  put_u32(body, kSlaveIp);
  put_u32(body, kSubnet);
  put_u32(body, 0);
  put_u32(body, 0);
  const char name[] = "ecat-conform";
  std::vector<std::uint8_t> dns(kDnsName, 0);
  std::copy(name, name + sizeof(name) - 1, dns.begin());
  body.insert(body.end(), dns.begin(), dns.end());
  return body;
}

// Gives the device kSlaveMac / kSlaveIp; a case result when it does not take them.
std::optional<CaseResult> set_ip(Context& ctx) {
  auto r = eoe_exchange(ctx, eoe_request(kSetIpRequest, set_ip_body()));
  if (!r) return CaseResult::failed("Set IP Parameter response, result 0x0000", r.error());
  if (r->type() != kSetIpResponse || r->word1 != kSuccess) return CaseResult::failed("Set IP Parameter response, result 0x0000", describe(*r));
  return std::nullopt;
}

std::uint16_t inet_checksum(ConstBytes data) {
  std::uint32_t sum = 0;
  for (std::size_t i = 0; i + 1 < data.size(); i += 2) sum += static_cast<std::uint32_t>((data[i] << 8) | data[i + 1]);
  if (data.size() % 2 != 0) sum += static_cast<std::uint32_t>(data.back() << 8);
  while (sum >> 16) sum = (sum & 0xFFFF) + (sum >> 16);
  return static_cast<std::uint16_t>(~sum);
}

void put_be16(std::uint8_t* p, std::uint16_t v) {
  p[0] = static_cast<std::uint8_t>(v >> 8);
  p[1] = static_cast<std::uint8_t>(v);
}
void put_be32(std::uint8_t* p, std::uint32_t v) {
  put_be16(p, static_cast<std::uint16_t>(v >> 16));
  put_be16(p + 2, static_cast<std::uint16_t>(v));
}
std::uint16_t be16(const std::uint8_t* p) { return static_cast<std::uint16_t>((p[0] << 8) | p[1]); }
std::uint32_t be32(const std::uint8_t* p) { return (static_cast<std::uint32_t>(be16(p)) << 16) | be16(p + 2); }

// An Ethernet frame of `size` bytes: ICMP echo request master -> slave.
std::vector<std::uint8_t> echo_request(std::size_t size, std::uint16_t sequence) {
  std::vector<std::uint8_t> f(size, 0);
  std::copy(kSlaveMac.begin(), kSlaveMac.end(), f.begin());
  std::copy(kMasterMac.begin(), kMasterMac.end(), f.begin() + 6);
  put_be16(&f[12], kEtherIpv4);
  std::uint8_t* ip = &f[kMinFrame];
  ip[0] = 0x45;  // IPv4, 5 words
  put_be16(ip + 2, static_cast<std::uint16_t>(size - kMinFrame));
  put_be16(ip + 4, sequence);
  ip[8] = 64;  // TTL
  ip[9] = kIcmp;
  put_be32(ip + 12, kMasterIp);
  put_be32(ip + 16, kSlaveIp);
  put_be16(ip + 10, inet_checksum(ConstBytes(ip, kIpHeader)));
  std::uint8_t* icmp = ip + kIpHeader;
  icmp[0] = kEchoRequest;
  put_be16(icmp + 4, kEchoId);
  put_be16(icmp + 6, sequence);
  for (std::size_t i = kMinFrame + kIpHeader + kIcmpHeader; i < size; ++i) f[i] = static_cast<std::uint8_t>(i * 13 + sequence);
  const std::size_t icmp_size = size - kMinFrame - kIpHeader;
  put_be16(icmp + 2, inet_checksum(ConstBytes(icmp, icmp_size)));
  return f;
}

// Bytes of frame data per fragment the master sends: what SM0 holds after
// the mailbox and EoE headers, down to a multiple of 32.
std::size_t fragment_room(Context& ctx) {
  const std::size_t room = ctx.info().sii.rx_mailbox_size - kMailboxHeader - kEoeHeader;
  return room / kBlock * kBlock;
}

// The frame in fragments as ETG.1000.6 numbers them; `wrong_number` gives
// the second fragment number 2 instead of 1.
Expected<void, std::string> send_frame(Context& ctx, const std::vector<std::uint8_t>& frame, std::uint8_t frame_number,
                                       bool wrong_number = false) {
  const std::size_t room = fragment_room(ctx);
  std::uint8_t fragment = 0;
  for (std::size_t at = 0; at < frame.size(); ++fragment) {
    const std::size_t n = std::min(room, frame.size() - at);
    const bool last = at + n == frame.size();
    const std::size_t offset = fragment == 0 ? (frame.size() + kBlock - 1) / kBlock : at / kBlock;
    const std::uint8_t number = (wrong_number && fragment == 1) ? 2 : fragment;
    std::vector<std::uint8_t> req(kEoeHeader + n);
    store_le<std::uint16_t>(req.data(), static_cast<std::uint16_t>(kFragmentData | (last ? kLastFragment : 0)));
    store_le<std::uint16_t>(req.data() + 2, static_cast<std::uint16_t>((number & kSixBits) | ((offset & kSixBits) << kOffsetShift) |
                                                                       ((frame_number & 0x0F) << kFrameShift)));
    std::copy_n(frame.begin() + static_cast<std::ptrdiff_t>(at), n, req.begin() + kEoeHeader);
    if (auto s = ctx.master().mailbox_send(ctx.slave(), mbx::kTypeEoe, req); !s) {
      return fail("send fragment " + std::to_string(fragment) + ": " + std::string(ecat::master::describe(s.error())));
    }
    at += n;
  }
  return {};
}

// One frame from the slave, its fragments' headers kept.
struct Received {
  std::vector<std::uint8_t> frame;
  std::vector<std::pair<std::uint16_t, std::uint16_t>> headers;  // word0, word1 of each fragment
  std::size_t data_bytes_before_last = 0;
};

Expected<Received, std::string> receive_frame(Context& ctx, Nanoseconds timeout) {
  Received r;
  for (unsigned i = 0; i < kMaxMessages; ++i) {
    auto m = receive_eoe(ctx, timeout);
    if (!m) return fail(m.error());
    if (m->type() != kFragmentData) continue;
    std::vector<std::uint8_t> data = m->body;
    const bool last = (m->word0 & kLastFragment) != 0;
    if (last && (m->word0 & kTimeAppended) != 0 && data.size() >= kTimestamp) data.resize(data.size() - kTimestamp);
    if ((m->word1 & kSixBits) == 0) {  // fragment 0 starts a frame: drop a partial one
      r = Received{};
    }
    r.headers.emplace_back(m->word0, m->word1);
    if (!last) r.data_bytes_before_last += data.size();
    r.frame.insert(r.frame.end(), data.begin(), data.end());
    if (last) return r;
  }
  return fail(std::string("no last fragment among ") + std::to_string(kMaxMessages) + " messages");
}

bool is_echo_reply(const std::vector<std::uint8_t>& f, std::uint16_t sequence) {
  if (f.size() < kMinFrame + kIpHeader + kIcmpHeader || be16(&f[12]) != kEtherIpv4) return false;
  const std::uint8_t* ip = &f[kMinFrame];
  const std::uint8_t* icmp = ip + kIpHeader;
  return ip[9] == kIcmp && icmp[0] == kEchoReply && be16(icmp + 4) == kEchoId && be16(icmp + 6) == sequence;
}

// Waits for the echo reply of `sequence` (other frames the device sends are passed over).
Expected<Received, std::string> receive_echo_reply(Context& ctx, std::uint16_t sequence, Nanoseconds timeout) {
  for (unsigned i = 0; i < kMaxMessages; ++i) {
    auto r = receive_frame(ctx, timeout);
    if (!r) return r;
    if (is_echo_reply(r->frame, sequence)) return r;
  }
  return fail(std::string("no echo reply"));
}

// What a correct echo reply to `request` is: addresses swapped, type 0, the
// same identifier, sequence and data, valid IPv4 and ICMP checksums.
std::string check_echo_reply(const std::vector<std::uint8_t>& request, const std::vector<std::uint8_t>& reply) {
  if (reply.size() < request.size()) return std::to_string(reply.size()) + " bytes for a " + std::to_string(request.size()) + "-byte request";
  if (!std::equal(reply.begin(), reply.begin() + 6, kMasterMac.begin()) || !std::equal(reply.begin() + 6, reply.begin() + 12, kSlaveMac.begin())) {
    return "MAC addresses not swapped";
  }
  const std::uint8_t* ip = &reply[kMinFrame];
  const std::size_t ip_len = be16(ip + 2);
  if (ip_len != request.size() - kMinFrame) return "IPv4 length " + std::to_string(ip_len);
  if (inet_checksum(ConstBytes(ip, kIpHeader)) != 0) return "bad IPv4 header checksum";
  if (be32(ip + 12) != kSlaveIp || be32(ip + 16) != kMasterIp) return "IP addresses not swapped";
  if (inet_checksum(ConstBytes(ip + kIpHeader, ip_len - kIpHeader)) != 0) return "bad ICMP checksum";
  const std::size_t data_at = kMinFrame + kIpHeader + kIcmpHeader;
  if (!std::equal(request.begin() + data_at, request.end(), reply.begin() + data_at)) return "echo data differs";
  return "echo reply, same data";
}

std::size_t big_frame_size(Context& ctx) { return std::min(kMaxFrame, 3 * fragment_room(ctx) + 17); }

std::optional<CaseResult> need_fragments(Context& ctx) {
  if (fragment_room(ctx) == 0) return CaseResult::failed("SM0 holds an EoE fragment", "SM0 of " + std::to_string(ctx.info().sii.rx_mailbox_size) + " bytes");
  if (fragment_room(ctx) >= kMaxFrame) return CaseResult::skip("SM0 holds a whole Ethernet frame: nothing to fragment");
  return std::nullopt;
}

// Sets the IP, pings with a frame of several fragments and returns the
// reply; failures as case results.
Expected<std::pair<std::vector<std::uint8_t>, Received>, CaseResult> ping(Context& ctx, std::uint16_t sequence, std::uint8_t frame_number) {
  if (auto c = set_ip(ctx)) return fail(*c);
  const auto request = echo_request(big_frame_size(ctx), sequence);
  if (auto s = send_frame(ctx, request, frame_number); !s) return fail(CaseResult::failed("send the echo request", s.error()));
  auto reply = receive_echo_reply(ctx, sequence, ctx.master().config().mailbox_timeout);
  if (!reply) {
    return fail(CaseResult::failed("echo reply to a " + std::to_string(request.size()) + "-byte frame in " +
                                       std::to_string((request.size() + fragment_room(ctx) - 1) / fragment_room(ctx)) + " fragments",
                                   reply.error()));
  }
  return std::make_pair(request, *reply);
}

// The fragments' headers as "f0/o47/n3 ...", and what they should be.
std::string numbering(const Received& r) {
  std::string s;
  for (const auto& [w0, w1] : r.headers) {
    if (!s.empty()) s += ' ';
    s += "f" + std::to_string(w1 & kSixBits) + "/o" + std::to_string((w1 >> kOffsetShift) & kSixBits) + "/n" +
         std::to_string(w1 >> kFrameShift) + ((w0 & kLastFragment) != 0 ? "/last" : "");
  }
  return s;
}

std::string expected_numbering(const Received& r) {
  std::string s;
  std::size_t at = 0;
  const std::uint16_t frame = r.headers.empty() ? 0 : static_cast<std::uint16_t>(r.headers.front().second >> kFrameShift);
  // The case checked that every fragment but the last carries the same
  // multiple of 32 bytes; the offsets count them.
  const std::size_t pieces = r.headers.size();
  const std::size_t per = pieces > 1 ? r.data_bytes_before_last / (pieces - 1) : 0;
  for (std::size_t k = 0; k < pieces; ++k) {
    if (!s.empty()) s += ' ';
    const std::size_t offset = k == 0 ? (r.frame.size() + kBlock - 1) / kBlock : at / kBlock;
    s += "f" + std::to_string(k) + "/o" + std::to_string(offset) + "/n" + std::to_string(frame) + (k + 1 == pieces ? "/last" : "");
    at += per;
  }
  return s;
}

}  // namespace

std::vector<Case> eoe_cases() {
  std::vector<Case> cases;
  cases.push_back({"eoe.set_ip_parameter", "ETG.1000.6 §5.7 EoE Set IP Parameter request (frame type 2, every field flagged) -> Set IP Parameter response (type 3), result 0x0000 (docs/eoe.md)",
                   [](Context& ctx) {
                     if (auto c = need_eoe(ctx)) return *c;
                     auto r = eoe_exchange(ctx, eoe_request(kSetIpRequest, set_ip_body()));
                     return CaseResult::compare("type 3, result 0x0000", r ? describe(*r) : r.error());
                   }});
  cases.push_back({"eoe.get_ip_parameter", "ETG.1000.6 §5.7 EoE Get IP Parameter request (type 6) -> response (type 7) with the IP flag and the address just set (docs/eoe.md)",
                   [](Context& ctx) {
                     if (auto c = need_eoe(ctx)) return *c;
                     if (auto c = set_ip(ctx)) return *c;
                     auto r = eoe_exchange(ctx, eoe_request(kGetIpRequest, {}));
                     if (!r) return CaseResult::failed("type 7", r.error());
                     if (r->type() == kSetIpResponse && r->word1 == kUnsupportedFrameType) {
                       return CaseResult::skip("Get IP Parameter not supported: " + describe(*r));
                     }
                     const std::string want = "type 7, result 0x0000, IP " + hex(kSlaveIp, 8);
                     if (r->type() != kGetIpResponse || r->body.size() < 4) return CaseResult::failed(want, describe(*r));
                     const auto flags = load_le<std::uint32_t>(r->body.data());
                     // Packed layout (only flagged fields) and fixed layout agree
                     // when the MAC is there: the IP follows it.
                     const std::size_t ip_at = 4 + ((flags & 1u) != 0 ? 6 : 0);
                     if ((flags & kHasIp) == 0 || r->body.size() < ip_at + 4) return CaseResult::failed(want, describe(*r) + ", flags " + hex(flags, 8));
                     return CaseResult::compare(want, describe(*r) + ", IP " + hex(load_le<std::uint32_t>(r->body.data() + ip_at), 8));
                   }});
  cases.push_back({"eoe.set_address_filter", "ETG.1000.6 §5.7 EoE Set Address Filter request (type 4, one MAC filter) -> response (type 5), result 0x0000 or 0x0401 no filter support (docs/eoe.md)",
                   [](Context& ctx) {
                     if (auto c = need_eoe(ctx)) return *c;
                     std::vector<std::uint8_t> body{0x01, 0x00};  // one MAC filter, no masks, broadcasts pass
                     put_mac(body, kMasterMac);
                     auto r = eoe_exchange(ctx, eoe_request(kSetFilterRequest, body));
                     if (!r) return CaseResult::failed("type 5, result 0x0000", r.error());
                     if (r->type() == kSetFilterResponse && r->word1 == kNoFilterSupport) return CaseResult::pass("type 5, result 0x0000 or 0x0401", describe(*r));
                     return CaseResult::compare("type 5, result 0x0000", describe(*r));
                   }});
  cases.push_back({"eoe.unknown_frame_type", "ETG.1000.6 §5.7 EoE: a request of a frame type the spec does not define (0x0A) -> result 0x0002 unsupported frame type (as SSC), or mailbox error 0x0004 service not supported (coe-mailbox.md §2)",
                   [](Context& ctx) {
                     if (auto c = need_eoe(ctx)) return *c;
                     auto r = eoe_exchange(ctx, eoe_request(kUnknownType, {}));
                     const std::string want = "result 0x0002 (or mailbox error 0x0004)";
                     if (!r) {
                       return r.error() == "mailbox error " + hex(kServiceNotSupported, 4) ? CaseResult::pass(want, r.error())
                                                                                           : CaseResult::failed(want, r.error());
                     }
                     return r->word1 == kUnsupportedFrameType ? CaseResult::pass(want, describe(*r)) : CaseResult::failed(want, describe(*r));
                   }});
  cases.push_back({"eoe.fragment_reassembly", "ETG.1000.6 §5.7 EoE fragment data: an Ethernet frame larger than SM0 sent in fragments (number 0.., offset/size in 32-byte units) is put together: the ICMP echo request gets its reply with the same data",
                   [](Context& ctx) {
                     if (auto c = need_eoe(ctx)) return *c;
                     if (auto c = need_fragments(ctx)) return *c;
                     auto r = ping(ctx, 1, 1);
                     if (!r) return r.error();
                     return CaseResult::compare("echo reply, same data", check_echo_reply(r->first, r->second.frame));
                   }});
  cases.push_back({"eoe.reply_fragment_numbering", "ETG.1000.6 §5.7 EoE fragments to the master: numbers 0, 1, ..; fragment 0's offset field = frame size in 32-byte units (rounded up), later ones = bytes before them / 32; one frame number; last-fragment bit on the last only",
                   [](Context& ctx) {
                     if (auto c = need_eoe(ctx)) return *c;
                     if (auto c = need_fragments(ctx)) return *c;
                     auto r = ping(ctx, 2, 2);
                     if (!r) return r.error();
                     const Received& rx = r->second;
                     if (rx.headers.size() > 1 && rx.data_bytes_before_last % (rx.headers.size() - 1) != 0) {
                       return CaseResult::failed("fragments of one size but the last", numbering(rx));
                     }
                     if (rx.headers.size() > 1 && (rx.data_bytes_before_last / (rx.headers.size() - 1)) % kBlock != 0) {
                       return CaseResult::failed("fragments of a multiple of 32 bytes but the last", std::to_string(rx.data_bytes_before_last) + " bytes before the last");
                     }
                     return CaseResult::compare(expected_numbering(rx), numbering(rx));
                   }});
  cases.push_back({"eoe.bad_fragment_number_dropped", "ETG.1000.6 §5.7 EoE: a frame whose second fragment has number 2 is dropped (no echo reply); CoE after it is answered (SDO upload 1000h) and the next frame gets its reply",
                   [](Context& ctx) {
                     if (auto c = need_eoe(ctx)) return *c;
                     if (auto c = need_fragments(ctx)) return *c;
                     if (auto c = set_ip(ctx)) return *c;
                     const auto broken = echo_request(big_frame_size(ctx), 3);
                     if (auto s = send_frame(ctx, broken, 3, true); !s) return CaseResult::failed("send", s.error());
                     std::string seen;
                     auto none = receive_echo_reply(ctx, 3, kNoAnswerWait);
                     seen += none ? "echo reply" : "no echo reply";
                     if (ctx.info().sii.has_coe()) {
                       auto type = ctx.coe().upload_value(0x1000, 0);
                       seen += type ? ", 1000h read" : ", 1000h " + describe_sdo(type.error());
                     } else {
                       seen += ", 1000h read";  // no CoE: nothing to lose
                     }
                     const auto good = echo_request(big_frame_size(ctx), 4);
                     if (auto s = send_frame(ctx, good, 4); !s) return CaseResult::failed("send", s.error());
                     auto reply = receive_echo_reply(ctx, 4, ctx.master().config().mailbox_timeout);
                     seen += reply ? ", next echo answered" : ", next echo: " + reply.error();
                     return CaseResult::compare("no echo reply, 1000h read, next echo answered", seen);
                   }});
  return cases;
}

}  // namespace ecat::master::conformance
